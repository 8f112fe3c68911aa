// Live output holds nothing back: every point of a frame says whose it is, a track (by the id
// it was first published with, kept when it is confirmed: provisional is a flag) or none.
#include <gtest/gtest.h>

#include "track/tracker.h"

namespace mocap {
namespace {

ReconstructedPoint PointAt(double x, int views) {
  ReconstructedPoint point;
  point.point_in_world = Eigen::Vector3d(x, 0.0, 1000.0);
  point.num_views = views;
  return point;
}

TEST(PointIdentity, OneIdFromTheFirstFrameConfirmedUnderTheMarkerOfItsSamples) {
  TrackerOptions options;
  options.rate_hz = 100.0;
  options.birth_min_views = 3;  // the far point of two views never starts a track
  Tracker tracker(options);
  std::vector<TrackSample> samples;
  uint64_t id = 0;
  for (uint64_t frame = 0; frame < 6; ++frame) {
    // A marker moving 2 mm per frame seen by 4 cameras, a far point seen by 2 (too few to start a
    // track here), both reported in every frame.
    const std::vector<ReconstructedPoint> points = {PointAt(2.0 * frame, 4), PointAt(900.0, 2)};
    tracker.Predict(frame);
    samples.clear();
    tracker.Update(frame, points, &samples);
    const std::vector<PointIdentity>& ids = tracker.point_identities();
    ASSERT_EQ(ids.size(), points.size());
    EXPECT_FALSE(ids[1].confirmed());
    EXPECT_EQ(ids[1].id, 0u);
    ASSERT_NE(ids[0].id, 0u) << frame;
    if (frame == 0) id = ids[0].id;
    EXPECT_EQ(ids[0].id, id) << frame;
    if (frame + 1 < static_cast<uint64_t>(options.birth_frames)) {
      EXPECT_FALSE(ids[0].confirmed()) << frame;
      EXPECT_TRUE(samples.empty());
    } else {
      ASSERT_TRUE(ids[0].confirmed()) << frame;
      ASSERT_FALSE(samples.empty());
      for (const TrackSample& s : samples) EXPECT_EQ(s.marker, ids[0].marker);
    }
  }
}

TEST(PointIdentity, SerialsAreNeverReused) {
  Tracker tracker(TrackerOptions{});
  std::vector<TrackSample> samples;
  std::vector<uint64_t> serials;
  // A point that appears for one frame and vanishes: its tentative track is freed and the slot
  // reused by the next one, under a new serial.
  for (uint64_t frame = 0; frame < 12; frame += 3) {
    tracker.Predict(frame);
    tracker.Update(frame, {PointAt(500.0 * static_cast<double>(frame), 4)}, &samples);
    ASSERT_EQ(tracker.point_identities().size(), 1u);
    serials.push_back(tracker.point_identities()[0].id);
    tracker.Predict(frame + 1);
    tracker.Update(frame + 1, {}, &samples);
    EXPECT_TRUE(tracker.point_identities().empty());
  }
  for (size_t i = 1; i < serials.size(); ++i) EXPECT_GT(serials[i], serials[i - 1]);
}

}  // namespace
}  // namespace mocap

// The live chain on a simulated rig, without sockets or files: every marker published in its own
// frame (provisional first, then with a confirmed identity that stays), the frame's times taken
// from its cameras and the clock, a defined rigid body posed from its markers.
#include "pipeline/live_reconstruction.h"

#include <algorithm>
#include <map>
#include <vector>

#include <gtest/gtest.h>

#include "bodies/body_definition.h"
#include "simcore/test_scenes.h"

namespace mocap::pipeline {
namespace {

constexpr double kRateHz = 120.0;
constexpr int kFrames = 120;

class LiveReconstructionTest : public ::testing::Test {
 protected:
  LiveReconstructionTest()
      : rig_(testing::MakeRingRig(8, 4000.0, 2200.0, Eigen::Vector3d(0, 0, 1000))),
        motion_(12, 4, 7),
        projector_(rig_, testing::ProjectionFaults(), 8) {}

  // Frame f of the motion, with camera i triggered at 1000 + f * 10 + (n - i) and its last
  // datagram received at 5000 + f * 10 + i, so that the earliest trigger is the last camera's
  // and the latest receive the last camera's.
  FrameSet Frame(uint64_t f) {
    markers_ = motion_.At(static_cast<double>(f) / kRateHz);
    FrameSet set;
    testing::BlobTruth truth;
    projector_.Project(f, markers_, &set, &truth);
    const uint64_t n = set.cameras.size();
    for (uint64_t i = 0; i < n; ++i) {
      set.cameras[i].trigger_time_ns = 1000 + f * 10 + (n - i);
      set.cameras[i].receive_time_ns = 5000 + f * 10 + i;
    }
    return set;
  }

  // The truth marker nearest to `p`, and how far it is.
  int Nearest(const Eigen::Vector3d& p, double* distance_mm) const {
    int best = -1;
    *distance_mm = 1e300;
    for (size_t m = 0; m < markers_.size(); ++m) {
      const double d = (markers_[m] - p).norm();
      if (d < *distance_mm) {
        *distance_mm = d;
        best = static_cast<int>(m);
      }
    }
    return best;
  }

  Rig rig_;
  testing::SyntheticMotion motion_;
  testing::FrameProjector projector_;
  std::vector<Eigen::Vector3d> markers_;
};

TEST_F(LiveReconstructionTest, EveryMarkerInItsOwnFrameWithAnIdentityThatStays) {
  LiveReconstruction live(rig_, kRateHz);
  std::map<int, int> marker_of_truth;  // once confirmed: truth marker -> published marker
  int first_all_confirmed = -1;
  for (int f = 0; f < kFrames; ++f) {
    const FrameSet set = Frame(f);
    const LiveFrame& frame = live.Process(set, [f] { return uint64_t{42} + f; });
    ASSERT_EQ(frame.frame_number, static_cast<uint64_t>(f));
    ASSERT_EQ(frame.cameras, static_cast<int>(set.cameras.size()));
    EXPECT_EQ(frame.trigger_time_ns, 1000 + f * 10 + 1u);
    EXPECT_EQ(frame.last_receive_ns, 5000 + f * 10 + set.cameras.size() - 1);
    EXPECT_EQ(frame.publish_ns, 42u + f);
    ASSERT_EQ(frame.points.size(), markers_.size()) << "frame " << f;
    EXPECT_FALSE(frame.label_names);
    EXPECT_TRUE(frame.bodies.empty());

    bool all_confirmed = true;
    for (const LivePoint& p : frame.points) {
      double distance_mm = 0.0;
      const int truth = Nearest(p.position, &distance_mm);
      EXPECT_LT(distance_mm, 1.0) << "frame " << f;
      EXPECT_GE(p.views, 2);
      EXPECT_EQ(p.label, -1);
      if (f == 0) {
        EXPECT_TRUE(p.provisional()) << "a track is confirmed only after frames of it";
      }
      if (p.provisional()) {
        all_confirmed = false;
        continue;
      }
      const auto [it, inserted] = marker_of_truth.emplace(truth, p.marker);
      EXPECT_EQ(it->second, p.marker) << "frame " << f << ": truth marker " << truth << " changed identity";
    }
    if (all_confirmed && first_all_confirmed < 0) first_all_confirmed = f;
  }
  ASSERT_GE(first_all_confirmed, 1);
  EXPECT_LT(first_all_confirmed, kFrames / 2);
  ASSERT_EQ(marker_of_truth.size(), markers_.size());
  std::vector<int> published;
  for (const auto& [truth, marker] : marker_of_truth) published.push_back(marker);
  std::sort(published.begin(), published.end());
  EXPECT_EQ(std::unique(published.begin(), published.end()), published.end()) << "two markers share an id";
}

TEST_F(LiveReconstructionTest, ConfirmedSamplesComeWithTheFrames) {
  LiveReconstruction live(rig_, kRateHz);
  size_t samples = 0;
  for (int f = 0; f < kFrames; ++f) samples += live.Process(Frame(f), [] { return uint64_t{0}; }).samples.size();
  // Every confirmed marker's sample once, the frames before its confirmation included.
  EXPECT_GE(samples, markers_.size() * (kFrames - 5));
  EXPECT_LE(samples, markers_.size() * kFrames);
}

TEST_F(LiveReconstructionTest, DefinedBodyPosedFromItsMarkers) {
  const std::vector<Eigen::Vector3d> start = motion_.At(0.0);
  const std::vector<Eigen::Vector3d> body(start.begin(), start.begin() + 4);
  LiveReconstruction live(rig_, kRateHz, {}, {DefineBody("box", body)});
  int tracked = 0;
  for (int f = 0; f < kFrames; ++f) {
    const LiveFrame& frame = live.Process(Frame(f), [] { return uint64_t{0}; });
    ASSERT_EQ(frame.bodies.size(), 1u);
    const LiveBody& b = frame.bodies[0];
    EXPECT_EQ(b.id, 1u);
    EXPECT_EQ(b.name, "box");
    if (!b.tracked) continue;
    ++tracked;
    EXPECT_EQ(b.markers, 4);
    EXPECT_LT(b.mean_error_mm, 1.0);
  }
  EXPECT_GE(tracked, kFrames - 10);
}

}  // namespace
}  // namespace mocap::pipeline

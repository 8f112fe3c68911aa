// Gap filling: short gaps become splines, long gaps keep predictions, rows come out in order.
#include "track/gap_filler.h"

#include <map>

#include <gtest/gtest.h>

namespace mocap {
namespace {

TrackSample Measured(int marker, uint64_t frame, const Eigen::Vector3d& position,
                     const Eigen::Vector3d& velocity) {
  TrackSample s;
  s.marker = marker;
  s.frame_number = frame;
  s.position = position;
  s.velocity_per_frame = velocity;
  return s;
}

TEST(GapFiller, ShortGapBecomesSplineThroughParabola) {
  GapFillOptions options;
  options.max_spline_gap = 8;
  options.window_frames = 20;
  std::map<uint64_t, std::vector<TrackSample>> out;
  GapFiller filler(options, [&](uint64_t frame, const std::vector<TrackSample>& row) {
    EXPECT_TRUE(out.empty() || frame == out.rbegin()->first + 1);
    out[frame] = row;
  });
  // x = f^2 / 10: a cubic Hermite with exact end velocities reproduces it exactly.
  const auto at = [](double f) { return Eigen::Vector3d(f * f / 10.0, 5.0, -f); };
  const auto velocity = [](double f) { return Eigen::Vector3d(f / 5.0, 0.0, -1.0); };
  for (uint64_t f = 0; f < 40; ++f) {
    std::vector<TrackSample> samples;
    if (f < 10 || f > 15) samples.push_back(Measured(0, f, at(f), velocity(f)));
    filler.Add(f, samples);
  }
  filler.Finish();
  ASSERT_EQ(out.size(), 40u);
  for (uint64_t f = 10; f <= 15; ++f) {
    ASSERT_EQ(out[f].size(), 1u) << f;
    EXPECT_EQ(out[f][0].kind, SampleKind::kFilled);
    EXPECT_LT((out[f][0].position - at(f)).norm(), 1e-9);
  }
  EXPECT_EQ(filler.filled_samples(), 6);
}

TEST(GapFiller, LongGapKeepsPredictionsAndHoles) {
  GapFillOptions options;
  options.max_spline_gap = 3;
  options.window_frames = 10;
  std::map<uint64_t, std::vector<TrackSample>> out;
  GapFiller filler(options, [&](uint64_t frame, const std::vector<TrackSample>& row) { out[frame] = row; });
  for (uint64_t f = 0; f < 30; ++f) {
    std::vector<TrackSample> samples;
    if (f < 10 || f > 15) samples.push_back(Measured(0, f, Eigen::Vector3d(f, 0, 0), Eigen::Vector3d(1, 0, 0)));
    if (f == 11) {
      TrackSample predicted = Measured(0, f, Eigen::Vector3d(11.5, 0, 0), Eigen::Vector3d(1, 0, 0));
      predicted.kind = SampleKind::kPredicted;
      samples.push_back(predicted);
    }
    filler.Add(f, samples);
  }
  filler.Finish();
  EXPECT_TRUE(out[10].empty());
  ASSERT_EQ(out[11].size(), 1u);
  EXPECT_EQ(out[11][0].kind, SampleKind::kPredicted);
  EXPECT_EQ(filler.filled_samples(), 0);
}

TEST(GapFiller, MemoryIsBoundedByTheWindow) {
  GapFillOptions options;
  options.window_frames = 16;
  size_t rows = 0;
  GapFiller filler(options, [&](uint64_t, const std::vector<TrackSample>&) { ++rows; });
  for (uint64_t f = 0; f < 1000; ++f) {
    filler.Add(f, {Measured(0, f, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero())});
    EXPECT_EQ(rows + 16, f + 1 > 16 ? f + 1 : rows + 16);
  }
  // A sample older than the window is dropped, not written out of order.
  filler.Add(1000, {Measured(0, 500, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero())});
  EXPECT_EQ(filler.dropped_samples(), 1);
}

// A pause longer than the window costs nothing per missing frame: the rows around it come out,
// the frames inside it do not, whatever the jump (up to the largest frame number).
TEST(GapFiller, PauseLongerThanTheWindowWritesNoRowsInside) {
  for (const uint64_t resume : {uint64_t{100}, uint64_t{1'000'000'000}, ~uint64_t{0}}) {
    GapFillOptions options;
    options.window_frames = 16;
    std::vector<uint64_t> frames;
    GapFiller filler(options, [&](uint64_t frame, const std::vector<TrackSample>&) { frames.push_back(frame); });
    for (uint64_t f = 0; f < 5; ++f) filler.Add(f, {Measured(0, f, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero())});
    filler.Add(resume, {Measured(0, resume, Eigen::Vector3d::Ones(), Eigen::Vector3d::Zero())});
    filler.Finish();
    EXPECT_EQ(frames, (std::vector<uint64_t>{0, 1, 2, 3, 4, resume}));
    EXPECT_EQ(filler.filled_samples(), 0);
  }
}

}  // namespace
}  // namespace mocap

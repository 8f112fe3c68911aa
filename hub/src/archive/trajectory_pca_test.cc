// PCA compression: the error bound holds on decoded data, gaps come back exactly, fixed K is
// honoured, an exactly low-rank motion needs no more components than its rank, groups split the
// blocks, bad options are refused; the shared recordings stay within the bound.
#include "archive/trajectory_pca.h"

#include <cmath>
#include <filesystem>
#include <stdexcept>

#include <gtest/gtest.h>

#include "io/trc.h"
#include "simcore/synthetic_motion.h"

namespace mocap {
namespace {

MarkerTrajectories WalkerWithGaps() {
  SyntheticMotionOptions options;
  options.markers = 24;
  options.frames = 500;
  options.first_frame = 1000;
  MarkerTrajectories motion = MakeSyntheticMotion(options);
  // A long gap, a one-frame gap, a marker missing at the start and one at the end.
  for (size_t t = 100; t < 160; ++t) motion.At(t, 3) = MarkerTrajectories::Gap();
  motion.At(250, 7) = MarkerTrajectories::Gap();
  for (size_t t = 0; t < 30; ++t) motion.At(t, 11) = MarkerTrajectories::Gap();
  for (size_t t = 470; t < 500; ++t) motion.At(t, 20) = MarkerTrajectories::Gap();
  return motion;
}

TEST(TrajectoryPca, ErrorBoundHoldsAndGapsStayGaps) {
  const MarkerTrajectories motion = WalkerWithGaps();
  for (double bound : {2.0, 0.5, 0.1}) {
    TrajectoryPcaOptions options;
    options.window_frames = 128;
    options.max_error_mm = bound;
    const CompressedTrajectories compressed = CompressTrajectories(motion, {}, options);
    const MarkerTrajectories decoded = DecompressTrajectories(compressed);
    ASSERT_EQ(decoded.names, motion.names);
    ASSERT_EQ(decoded.frame_numbers, motion.frame_numbers);
    ASSERT_EQ(decoded.rate_hz, motion.rate_hz);
    for (size_t i = 0; i < motion.points.size(); ++i)
      ASSERT_EQ(MarkerTrajectories::IsGap(decoded.points[i]), MarkerTrajectories::IsGap(motion.points[i])) << i;
    EXPECT_LE(TrajectoryRmsError(motion, decoded), bound);
    EXPECT_EQ(compressed.blocks.size(), 4u);  // 500 frames in windows of 128, one group
  }
}

TEST(TrajectoryPca, TighterBoundsTakeMoreComponents) {
  const MarkerTrajectories motion = WalkerWithGaps();
  int previous = -1;
  for (double bound : {5.0, 1.0, 0.2, 0.05}) {
    TrajectoryPcaOptions options;
    options.max_error_mm = bound;
    const CompressedTrajectories compressed = CompressTrajectories(motion, {}, options);
    int total = 0;
    for (const PcaBlock& block : compressed.blocks) total += block.components;
    EXPECT_GE(total, previous) << bound;
    previous = total;
  }
  EXPECT_GT(previous, 0);
}

TEST(TrajectoryPca, FixedComponentsAreKeptAndErrorFallsWithThem) {
  const MarkerTrajectories motion = WalkerWithGaps();
  double previous = INFINITY;
  for (int k : {1, 3, 8, 20}) {
    TrajectoryPcaOptions options;
    options.components = k;
    const CompressedTrajectories compressed = CompressTrajectories(motion, {}, options);
    for (const PcaBlock& block : compressed.blocks) {
      EXPECT_EQ(block.components, k);
      EXPECT_EQ(block.weights.size(), 3 * motion.NumMarkers() * static_cast<size_t>(k));
    }
    const double error = TrajectoryRmsError(motion, DecompressTrajectories(compressed));
    EXPECT_LT(error, previous) << k;
    previous = error;
  }
}

TEST(TrajectoryPca, ExactlyLowRankMotionNeedsOnlyItsRank) {
  // Every marker moves along the same two time signals with its own weights: rank 2 after centring.
  MarkerTrajectories motion;
  motion.rate_hz = 100.0;
  for (int m = 0; m < 10; ++m) motion.names.push_back("M" + std::to_string(m));
  for (int t = 0; t < 300; ++t) {
    const size_t f = motion.AddFrame(static_cast<uint64_t>(t));
    const double a = std::sin(0.05 * t) * 100.0, b = std::cos(0.013 * t) * 40.0;
    for (int m = 0; m < 10; ++m)
      motion.At(f, static_cast<size_t>(m)) = Eigen::Vector3d(10.0 * m + a, 0.5 * m * b, 200.0 - m + a - b);
  }
  TrajectoryPcaOptions options;
  options.window_frames = 300;
  options.max_error_mm = 0.01;
  const CompressedTrajectories compressed = CompressTrajectories(motion, {}, options);
  ASSERT_EQ(compressed.blocks.size(), 1u);
  EXPECT_LE(compressed.blocks[0].components, 2);
  EXPECT_LE(TrajectoryRmsError(motion, DecompressTrajectories(compressed)), 0.01);
}

TEST(TrajectoryPca, GroupsSplitBlocksAndEveryMarkerNeedsExactlyOne) {
  const MarkerTrajectories motion = WalkerWithGaps();
  std::vector<std::vector<int>> groups(3);
  for (int m = 0; m < 24; ++m) groups[static_cast<size_t>(m % 3)].push_back(m);
  TrajectoryPcaOptions options;
  options.window_frames = 250;
  const CompressedTrajectories compressed = CompressTrajectories(motion, groups, options);
  EXPECT_EQ(compressed.blocks.size(), 6u);
  EXPECT_EQ(compressed.blocks[1].mean.size(), 24u);  // 8 markers x 3
  EXPECT_LE(TrajectoryRmsError(motion, DecompressTrajectories(compressed)), 0.5);

  groups[0].push_back(1);  // marker 1 in two groups
  EXPECT_THROW(CompressTrajectories(motion, groups, options), std::invalid_argument);
  groups[0].pop_back();
  groups[2].pop_back();  // a marker in no group
  EXPECT_THROW(CompressTrajectories(motion, groups, options), std::invalid_argument);
}

TEST(TrajectoryPca, OptionsRefuseOutOfRangeValues) {
  TrajectoryPcaOptions options;
  options.window_frames = 0;
  EXPECT_THROW(options.Check(), std::invalid_argument);
  options = {};
  options.components = 256;
  EXPECT_THROW(options.Check(), std::invalid_argument);
  options = {};
  options.max_error_mm = std::nan("");
  EXPECT_THROW(options.Check(), std::invalid_argument);
  options.components = 4;  // the bound is unused then
  EXPECT_NO_THROW(options.Check());
}

TEST(TrajectoryPca, SharedRecordingsStayWithinTheBound) {
  const std::string dir = std::string(MOCAP_SHARED_DIR) + "/data/motions";
  if (!std::filesystem::is_directory(dir)) GTEST_SKIP() << "../shared/data missing: no " << dir;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    if (entry.path().extension() != ".trc") continue;
    const MarkerTrajectories motion = ReadTrc(entry.path().string());
    const CompressedTrajectories compressed = CompressTrajectories(motion, {}, TrajectoryPcaOptions{});
    const MarkerTrajectories decoded = DecompressTrajectories(compressed);
    EXPECT_LE(TrajectoryRmsError(motion, decoded), 0.5) << entry.path();
    for (size_t i = 0; i < motion.points.size(); ++i)
      ASSERT_EQ(MarkerTrajectories::IsGap(decoded.points[i]), MarkerTrajectories::IsGap(motion.points[i])) << entry.path();
  }
}

}  // namespace
}  // namespace mocap

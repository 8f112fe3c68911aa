// sim wand: the waved volume is where the cameras look, the wand keeps its length, the path
// stays inside and covers the volume at a hand's speed, seeds replay, the L-frame follows.
#include "simcore/wand.h"

#include <cmath>
#include <set>
#include <stdexcept>

#include <gtest/gtest.h>

#include "simcore/ring_rig.h"

namespace mocap {
namespace {

Rig TestRig(int cameras) {
  MotionVolume person;
  person.min = Eigen::Vector3d(-1000.0, -1000.0, 0.0);
  person.max = Eigen::Vector3d(1000.0, 1000.0, 1800.0);
  person.up_axis = 2;
  RingRigOptions options;
  options.cameras = cameras;
  return MakeRingRig(person, options);
}

TEST(WandVolumeTest, VolumeLiesWhereTheCamerasLookAndFindsTheUpAxis) {
  const Rig rig = TestRig(8);
  const MotionVolume volume = WandVolume(rig, 3, -1);
  EXPECT_EQ(volume.up_axis, 2);
  const Eigen::Vector3d centre = volume.Center();
  EXPECT_LT(std::abs(centre.x()), 400.0);
  EXPECT_LT(std::abs(centre.y()), 400.0);
  const Eigen::Vector3d size = volume.max - volume.min;
  EXPECT_GT(size.x(), 1500.0);
  EXPECT_GT(size.y(), 1500.0);
  EXPECT_GT(size.z(), 800.0);
  // Asking for more cameras than exist leaves no volume.
  EXPECT_THROW(WandVolume(rig, 9, -1), std::runtime_error);
}

TEST(WandMotionTest, WandKeepsItsLengthAndCoversTheVolume) {
  const Rig rig = TestRig(8);
  WandMotionOptions options;
  options.frames = 3000;
  options.middle_marker_mm = 180.0;
  const MarkerTrajectories motion = MakeWandMotion(rig, options);
  ASSERT_EQ(motion.NumFrames(), 3000u);
  ASSERT_EQ(motion.NumMarkers(), 3u);
  const MotionVolume volume = WandVolume(rig, options.min_cameras, -1);
  std::set<int> cells;
  double path = 0.0;
  for (size_t f = 0; f < motion.NumFrames(); ++f) {
    const Eigen::Vector3d a = motion.At(f, 0), m = motion.At(f, 1), b = motion.At(f, 2);
    EXPECT_NEAR((b - a).norm(), 500.0, 1e-9);
    EXPECT_NEAR((m - a).norm(), 180.0, 1e-9);
    const Eigen::Vector3d centre = 0.5 * (a + b);
    EXPECT_TRUE((centre.array() >= volume.min.array() - 1e-9).all() &&
                (centre.array() <= volume.max.array() + 1e-9).all());
    const Eigen::Vector3d cell = (centre - volume.min).cwiseQuotient(volume.max - volume.min) * 3.0;
    cells.insert(std::min(2, static_cast<int>(cell.x())) * 9 + std::min(2, static_cast<int>(cell.y())) * 3 +
                 std::min(2, static_cast<int>(cell.z())));
    if (f > 0) path += (centre - 0.5 * (motion.At(f - 1, 0) + motion.At(f - 1, 2))).norm();
  }
  EXPECT_GE(cells.size(), 16u);  // of the 27 cells of the volume box, in 30 s of waving
  const double speed = path / (motion.NumFrames() / motion.rate_hz);
  EXPECT_GT(speed, 0.4 * options.speed_mm_s);
  EXPECT_LT(speed, 2.0 * options.speed_mm_s);
}

TEST(WandMotionTest, SeedReplaysAndLFrameFollowsTheWave) {
  const Rig rig = TestRig(6);
  WandMotionOptions options;
  options.frames = 200;
  options.lframe_frames = 10;
  options.lframe_markers = {{0, 0, 0}, {200, 0, 0}, {600, 0, 0}, {0, 400, 0}};
  const MarkerTrajectories first = MakeWandMotion(rig, options);
  const MarkerTrajectories second = MakeWandMotion(rig, options);
  ASSERT_EQ(first.NumFrames(), 210u);
  ASSERT_EQ(first.NumMarkers(), 6u);
  for (size_t i = 0; i < first.points.size(); ++i) {
    EXPECT_TRUE((first.points[i] - second.points[i]).norm() < 1e-12 ||
                (MarkerTrajectories::IsGap(first.points[i]) && MarkerTrajectories::IsGap(second.points[i])));
  }
  EXPECT_FALSE(first.Has(0, 2));
  EXPECT_TRUE(first.Has(0, 0));
  EXPECT_FALSE(first.Has(205, 0));
  EXPECT_EQ(first.At(205, 4), Eigen::Vector3d(600, 0, 0));
  options.seed = 2;
  const MarkerTrajectories other = MakeWandMotion(rig, options);
  EXPECT_GT((other.At(100, 0) - first.At(100, 0)).norm(), 1.0);
}

TEST(WandMotionTest, BadOptionsAreRefused) {
  const Rig rig = TestRig(4);
  WandMotionOptions options;
  options.wand_length_mm = 10.0;
  EXPECT_THROW(MakeWandMotion(rig, options), std::invalid_argument);
  options = WandMotionOptions();
  options.middle_marker_mm = 490.0;
  EXPECT_THROW(MakeWandMotion(rig, options), std::invalid_argument);
  options = WandMotionOptions();
  options.lframe_frames = 5;
  EXPECT_THROW(MakeWandMotion(rig, options), std::invalid_argument);
}

}  // namespace
}  // namespace mocap

// Tests of up-axis detection and ring rig placement: every camera sees the whole motion the
// right way up, placement is seeded and the options are checked.
#include "simcore/ring_rig.h"

#include <cmath>
#include <filesystem>
#include <stdexcept>

#include <gtest/gtest.h>

#include "io/trc.h"
#include "simcore/synthetic_motion.h"

namespace mocap {
namespace {

MarkerTrajectories Motion(int up_axis) {
  SyntheticMotionOptions options;
  options.up_axis = up_axis;
  options.frames = 200;
  return MakeSyntheticMotion(options);
}

TEST(MotionVolumeTest, DetectsEachUpAxis) {
  for (int axis = 0; axis < 3; ++axis) {
    EXPECT_EQ(DetectUpAxis(Motion(axis)), axis);
    const MotionVolume volume = ComputeMotionVolume(Motion(axis));
    EXPECT_EQ(volume.up_axis, axis);
    EXPECT_GT(volume.max[axis] - volume.min[axis], 1500.0);
  }
  MarkerTrajectories empty;
  empty.rate_hz = 100;
  empty.names = {"A"};
  empty.AddFrame(0);
  EXPECT_EQ(DetectUpAxis(empty), -1);
  EXPECT_THROW(ComputeMotionVolume(empty), std::runtime_error);
  // A corrupt coordinate (1e308) or one in the wrong unit far away is refused, not given a rig
  // with non-finite poses.
  for (double wild : {1e308, -1e308, 5e6}) {
    MarkerTrajectories motion = Motion(2);
    motion.At(10, 0).x() = wild;
    EXPECT_THROW(ComputeMotionVolume(motion, 2), std::runtime_error) << wild;
  }
}

TEST(RingRigTest, EveryCameraSeesTheWholeMotionUpright) {
  for (int axis = 0; axis < 3; ++axis) {
    SCOPED_TRACE(axis);
    const MarkerTrajectories motion = Motion(axis);
    const MotionVolume volume = ComputeMotionVolume(motion);
    RingRigOptions options;
    options.cameras = 6;
    const Rig rig = MakeRingRig(volume, options);
    ASSERT_EQ(rig.cameras.size(), 6u);
    for (const Camera& camera : rig.cameras) {
      EXPECT_GT(camera.CenterInWorld()[axis], volume.max[axis]);
      EXPECT_TRUE(camera.intrinsics.HasDistortion());
      // The world's up points up in the image (smaller row).
      Eigen::Vector2d low, high;
      ASSERT_TRUE(camera.ProjectToPixel(volume.Center(), &low));
      ASSERT_TRUE(camera.ProjectToPixel(volume.Center() + 300.0 * volume.Up(), &high));
      EXPECT_LT(high.y(), low.y() - 10.0);
      EXPECT_NEAR(high.x(), low.x(), 0.2 * (low.y() - high.y()));
      for (size_t f = 0; f < motion.NumFrames(); f += 10) {
        for (size_t m = 0; m < motion.NumMarkers(); ++m) {
          Eigen::Vector2d pixel;
          ASSERT_TRUE(camera.ProjectToPixel(motion.At(f, m), &pixel));
          EXPECT_TRUE(camera.InImage(pixel)) << pixel.transpose();
        }
      }
    }
    // Evenly spread around the volume: neighbours subtend about 360/6 degrees.
    for (size_t i = 0; i < rig.cameras.size(); ++i) {
      Eigen::Vector3d a = rig.cameras[i].CenterInWorld() - volume.Center();
      Eigen::Vector3d b = rig.cameras[(i + 1) % 6].CenterInWorld() - volume.Center();
      a[axis] = 0.0;
      b[axis] = 0.0;
      const double degrees = std::acos(a.normalized().dot(b.normalized())) * 180.0 / M_PI;
      EXPECT_NEAR(degrees, 60.0, 11.0);
    }
  }
}

TEST(RingRigTest, SeededAndOptionsChecked) {
  const MotionVolume volume = ComputeMotionVolume(Motion(1));
  RingRigOptions options;
  const Rig a = MakeRingRig(volume, options);
  const Rig b = MakeRingRig(volume, options);
  options.seed = 2;
  const Rig c = MakeRingRig(volume, options);
  EXPECT_EQ(a.cameras[3].translation, b.cameras[3].translation);
  EXPECT_EQ(a.cameras[3].intrinsics.distortion, b.cameras[3].intrinsics.distortion);
  EXPECT_NE(a.cameras[3].translation, c.cameras[3].translation);

  RingRigOptions bad;
  bad.cameras = 1;
  EXPECT_THROW(MakeRingRig(volume, bad), std::invalid_argument);
  bad = RingRigOptions();
  bad.fov_deg = 179.0;
  EXPECT_THROW(MakeRingRig(volume, bad), std::invalid_argument);
  bad = RingRigOptions();
  bad.width = 0;
  EXPECT_THROW(bad.Check(), std::invalid_argument);
}

// The shared real motions (README of ../shared/data): Y-up OpenSim walks and runs, a Z-up
// OptiTrack serve and a Z-up walk with gaps; an 8-camera ring must see every marker everywhere.
TEST(RingRigTest, SharedRealMotions) {
  const std::string dir = std::string(MOCAP_SHARED_DIR) + "/data/motions";
  if (!std::filesystem::exists(dir)) GTEST_SKIP() << "../shared/data missing: no " << dir;
  for (const auto& [file, up] : {std::pair<const char*, int>{"walk.trc", 1}, {"running.trc", 1},
                                 {"tennis_serve.trc", 2}, {"gaps_blank_cells.trc", 2}}) {
    SCOPED_TRACE(file);
    const MarkerTrajectories motion = ReadTrc(dir + "/" + file);
    EXPECT_EQ(DetectUpAxis(motion), up);
    const Rig rig = MakeRingRig(ComputeMotionVolume(motion), RingRigOptions());
    size_t seen = 0, total = 0;
    for (const Camera& camera : rig.cameras) {
      for (size_t f = 0; f < motion.NumFrames(); ++f) {
        for (size_t m = 0; m < motion.NumMarkers(); ++m) {
          if (!motion.Has(f, m)) continue;
          Eigen::Vector2d pixel;
          ++total;
          seen += camera.ProjectToPixel(motion.At(f, m), &pixel) && camera.InImage(pixel);
        }
      }
    }
    EXPECT_EQ(seen, total);
  }
}

}  // namespace
}  // namespace mocap

// A bump moves exactly the asked camera by exactly the asked angle and distance; its text form
// is parsed strictly.
#include "simcore/camera_bump.h"

#include <stdexcept>

#include <gtest/gtest.h>

#include "simcore/look_at.h"

namespace mocap {
namespace {

Rig TwoCameras() {
  Rig rig;
  for (uint32_t id = 1; id <= 2; ++id) {
    Camera camera;
    camera.id = id;
    camera.intrinsics.width = 1280;
    camera.intrinsics.height = 800;
    camera.intrinsics.fx = camera.intrinsics.fy = 1000.0;
    camera.intrinsics.cx = 640.0;
    camera.intrinsics.cy = 400.0;
    AimCamera(Eigen::Vector3d(3000.0 * id, -2000.0, 2500.0), Eigen::Vector3d(0.0, 0.0, 900.0),
              Eigen::Vector3d::UnitZ(), &camera);
    rig.cameras.push_back(camera);
  }
  return rig;
}

TEST(CameraBumpTest, MovesOnlyTheCameraByTheAskedAmounts) {
  const Rig before = TwoCameras();
  Rig after = before;
  CameraBump bump = ParseCameraBump("2:0.5:5");
  bump.seed = 9;
  ApplyCameraBump(bump, &after);
  EXPECT_EQ(after.cameras[0].rotation, before.cameras[0].rotation);
  EXPECT_EQ(after.cameras[0].translation, before.cameras[0].translation);
  const PoseChange change = ComparePoses(after.cameras[1], before.cameras[1]);
  EXPECT_NEAR(change.rotation_deg, 0.5, 1e-9);
  EXPECT_NEAR(change.centre_mm, 5.0, 1e-9);
  // The rotation stays a rotation.
  EXPECT_NEAR((after.cameras[1].rotation * after.cameras[1].rotation.transpose() - Eigen::Matrix3d::Identity()).norm(),
              0.0, 1e-12);
  // Another seed, another direction; the same seed, the same pose.
  Rig again = before;
  ApplyCameraBump(bump, &again);
  EXPECT_EQ(again.cameras[1].rotation, after.cameras[1].rotation);
  bump.seed = 10;
  Rig other = before;
  ApplyCameraBump(bump, &other);
  EXPECT_GT(ComparePoses(other.cameras[1], after.cameras[1]).centre_mm, 1e-6);
}

TEST(CameraBumpTest, UnknownCameraIsRefused) {
  Rig rig = TwoCameras();
  EXPECT_THROW(ApplyCameraBump(ParseCameraBump("3:0.5:5"), &rig), std::invalid_argument);
}

TEST(CameraBumpTest, TextIsParsedStrictly) {
  const CameraBump bump = ParseCameraBump("3:-0.25:12.5");
  EXPECT_EQ(bump.camera_id, 3u);
  EXPECT_DOUBLE_EQ(bump.degrees, -0.25);
  EXPECT_DOUBLE_EQ(bump.mm, 12.5);
  for (const char* bad : {"", "3", "3:0.5", "3:0.5:5:1", "0:0.5:5", "1.5:0.5:5", "x:0.5:5", "3:nan:5", "3:0.5:inf",
                          "3:200:5", "3:0.5:5mm", "3:0.5:1e9", "-1:0.5:5"}) {
    EXPECT_THROW(ParseCameraBump(bad), std::invalid_argument) << bad;
  }
}

}  // namespace
}  // namespace mocap

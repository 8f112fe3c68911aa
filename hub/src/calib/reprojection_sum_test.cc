// An observation of a point behind the camera is counted apart and never enters the RMS.
#include "calib/reprojection_sum.h"

#include <cmath>

#include <gtest/gtest.h>

namespace mocap {
namespace {

Camera TestCamera() {
  Camera camera;
  camera.intrinsics.width = 640;
  camera.intrinsics.height = 480;
  camera.intrinsics.fx = camera.intrinsics.fy = 500.0;
  camera.intrinsics.cx = 320.0;
  camera.intrinsics.cy = 240.0;
  return camera;
}

TEST(ReprojectionSum, PointBehindCameraIsCountedNotSummed) {
  const Camera camera = TestCamera();
  ReprojectionSum sum;
  // On the optical axis 1 m ahead: projects to the principal point; observed 3 px, 4 px off.
  EXPECT_TRUE(sum.Add(camera, Eigen::Vector3d(0, 0, 1000), Eigen::Vector2d(323, 244)));
  EXPECT_FALSE(sum.Add(camera, Eigen::Vector3d(0, 0, -1000), Eigen::Vector2d(320, 240)));
  EXPECT_FALSE(sum.Add(camera, Eigen::Vector3d(10, 0, 0), Eigen::Vector2d(320, 240)));
  EXPECT_EQ(sum.unprojected, 2u);
  EXPECT_EQ(sum.observations, 1u);
  EXPECT_NEAR(sum.RmsPx(), 5.0, 1e-9);
}

TEST(ReprojectionSum, EmptyIsZero) {
  ReprojectionSum sum;
  EXPECT_FALSE(sum.Add(TestCamera(), Eigen::Vector3d(0, 0, -1), Eigen::Vector2d(0, 0)));
  EXPECT_EQ(sum.RmsPx(), 0.0);
}

}  // namespace
}  // namespace mocap

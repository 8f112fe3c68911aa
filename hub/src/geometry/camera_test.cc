// Tests of the camera model: distortion inverse, projection / ray round trips, visibility.
#include "geometry/camera.h"

#include <cmath>
#include <random>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

namespace mocap {
namespace {

Camera MakeCamera(const std::array<double, 5>& distortion) {
  Camera camera;
  camera.id = 7;
  camera.intrinsics.width = 1280;
  camera.intrinsics.height = 800;
  camera.intrinsics.fx = 1000.0;
  camera.intrinsics.fy = 1005.0;
  camera.intrinsics.cx = 645.0;
  camera.intrinsics.cy = 398.0;
  camera.intrinsics.distortion = distortion;
  camera.rotation =
      (Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitX()) * Eigen::AngleAxisd(-0.7, Eigen::Vector3d::UnitY()))
          .toRotationMatrix();
  camera.translation = Eigen::Vector3d(100.0, -250.0, 3000.0);
  return camera;
}

TEST(CameraTest, UndistortInvertsDistortAcrossTheImage) {
  const std::array<std::array<double, 5>, 3> lenses = {{{-0.25, 0.08, 0.001, -0.0005, -0.01},
                                                        {0.1, -0.05, -0.002, 0.001, 0.02},
                                                        {-0.32, 0.12, 0.0, 0.0, -0.02}}};
  for (const auto& lens : lenses) {
    const Camera camera = MakeCamera(lens);
    double worst = 0.0;
    for (double x = -0.6; x <= 0.6; x += 0.05) {
      for (double y = -0.4; y <= 0.4; y += 0.05) {
        const Eigen::Vector2d normalized(x, y);
        const Eigen::Vector2d pixel = camera.NormalizedToPixel(camera.DistortNormalized(normalized));
        worst = std::max(worst, (camera.UndistortPixel(pixel) - normalized).norm());
      }
    }
    EXPECT_LT(worst, 1e-9);
  }
}

TEST(CameraTest, DistortionChangesPixelsSoTheInverseIsNotTrivial) {
  const Camera camera = MakeCamera({-0.25, 0.08, 0.001, -0.0005, -0.01});
  const Eigen::Vector2d normalized(0.5, 0.3);
  EXPECT_GT((camera.DistortNormalized(normalized) - normalized).norm(), 0.02);
}

TEST(CameraTest, CenterProjectsNowhereAndIsOnEveryRay) {
  const Camera camera = MakeCamera({-0.2, 0.05, 0.0, 0.0, 0.0});
  const Eigen::Vector3d center = camera.CenterInWorld();
  EXPECT_NEAR(camera.PointInCamera(center).norm(), 0.0, 1e-9);
  Eigen::Vector2d pixel(-1.0, -1.0);
  EXPECT_FALSE(camera.ProjectToPixel(center, &pixel));
  EXPECT_EQ(pixel, Eigen::Vector2d(-1.0, -1.0));
}

TEST(CameraTest, PointBehindCameraIsNotProjected) {
  const Camera camera = MakeCamera({0, 0, 0, 0, 0});
  const Eigen::Vector3d center = camera.CenterInWorld();
  const Eigen::Vector3d forward = camera.rotation.row(2).transpose();
  Eigen::Vector2d pixel;
  EXPECT_FALSE(camera.ProjectToPixel(center - 500.0 * forward, &pixel));
  EXPECT_TRUE(camera.ProjectToPixel(center + 500.0 * forward, &pixel));
  EXPECT_NEAR(pixel.x(), camera.intrinsics.cx, 1e-9);
  EXPECT_NEAR(pixel.y(), camera.intrinsics.cy, 1e-9);
}

TEST(CameraTest, ProjectAndRayRoundTrip) {
  const Camera camera = MakeCamera({-0.25, 0.08, 0.001, -0.0005, -0.01});
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> uniform(-800.0, 800.0);
  const Eigen::Vector3d center = camera.CenterInWorld();
  for (int i = 0; i < 200; ++i) {
    const Eigen::Vector3d point(uniform(rng), uniform(rng), uniform(rng));
    Eigen::Vector2d pixel;
    ASSERT_TRUE(camera.ProjectToPixel(point, &pixel));
    const Eigen::Vector3d ray = camera.RayDirectionInWorld(pixel);
    EXPECT_NEAR(ray.norm(), 1.0, 1e-12);
    const Eigen::Vector3d to_point = point - center;
    // Distance of the point from the back-projected ray.
    EXPECT_LT((to_point - to_point.dot(ray) * ray).norm(), 1e-6);
    EXPECT_GT(to_point.dot(ray), 0.0);
  }
}

TEST(CameraTest, ProjectionMatrixMatchesUndistortedProjection) {
  const Camera camera = MakeCamera({-0.25, 0.08, 0.001, -0.0005, -0.01});
  const Eigen::Vector3d point(120.0, -40.0, 300.0);
  Eigen::Vector2d pixel;
  ASSERT_TRUE(camera.ProjectToPixel(point, &pixel));
  const Eigen::Vector3d homogeneous = camera.ProjectionMatrix() * point.homogeneous();
  EXPECT_LT((homogeneous.hnormalized() - camera.UndistortPixel(pixel)).norm(), 1e-9);
}

TEST(CameraTest, InImageBounds) {
  const Camera camera = MakeCamera({0, 0, 0, 0, 0});
  EXPECT_TRUE(camera.InImage({0.0, 0.0}));
  EXPECT_TRUE(camera.InImage({1279.5, 799.5}));
  EXPECT_FALSE(camera.InImage({1280.0, 10.0}));
  EXPECT_FALSE(camera.InImage({10.0, -0.1}));
}

TEST(RigTest, FindById) {
  Rig rig;
  rig.cameras.push_back(MakeCamera({0, 0, 0, 0, 0}));
  rig.cameras.push_back(MakeCamera({0, 0, 0, 0, 0}));
  rig.cameras[1].id = 9;
  ASSERT_NE(rig.Find(9), nullptr);
  EXPECT_EQ(rig.Find(9), &rig.cameras[1]);
  EXPECT_EQ(rig.Find(7), &rig.cameras[0]);
  EXPECT_EQ(rig.Find(8), nullptr);
}

}  // namespace
}  // namespace mocap

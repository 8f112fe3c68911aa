// The table + Newton undistortion agrees with the camera's own iterative inverse.
#include "recon/undistorter.h"

#include <random>

#include <gtest/gtest.h>

namespace mocap {
namespace {

Camera WideAngleCamera() {
  Camera camera;
  camera.intrinsics.width = 1280;
  camera.intrinsics.height = 800;
  camera.intrinsics.fx = 900.0;
  camera.intrinsics.fy = 905.0;
  camera.intrinsics.cx = 645.0;
  camera.intrinsics.cy = 398.0;
  camera.intrinsics.distortion = {-0.28, 0.09, 0.0008, -0.0005, -0.012};
  return camera;
}

TEST(Undistorter, MatchesIterativeInverseOverTheImage) {
  const Camera camera = WideAngleCamera();
  const Undistorter undistorter(camera);
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> x(-5.0, 1285.0), y(-5.0, 805.0);
  double worst = 0.0;
  for (int i = 0; i < 5000; ++i) {
    const Eigen::Vector2d pixel(x(rng), y(rng));
    worst = std::max(worst, (undistorter.Undistort(pixel) - camera.UndistortPixel(pixel)).norm());
  }
  // In pixels: 1e-4 px is two orders under the best centroid's precision (~0.01 px).
  EXPECT_LT(worst * camera.intrinsics.fx, 1e-4);
}

TEST(Undistorter, RoundTripsProjectedPoints) {
  const Camera camera = WideAngleCamera();
  const Undistorter undistorter(camera);
  for (double u = -0.6; u <= 0.6; u += 0.1) {
    for (double v = -0.4; v <= 0.4; v += 0.1) {
      const Eigen::Vector2d pixel = camera.NormalizedToPixel(camera.DistortNormalized({u, v}));
      EXPECT_LT((undistorter.Undistort(pixel) - Eigen::Vector2d(u, v)).norm() * camera.intrinsics.fx, 1e-4);
    }
  }
}

TEST(Undistorter, PinholeCameraPassesThrough) {
  Camera camera = WideAngleCamera();
  camera.intrinsics.distortion = {0, 0, 0, 0, 0};
  const Undistorter undistorter(camera);
  const Eigen::Vector2d pixel(100.0, 700.0);
  EXPECT_LT((undistorter.Undistort(pixel) - camera.UndistortPixel(pixel)).norm(), 1e-15);
}

}  // namespace
}  // namespace mocap

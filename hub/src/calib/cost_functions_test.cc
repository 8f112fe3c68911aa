// Cost functors: their residuals agree with the shared camera model, and their automatic
// derivatives agree with numeric ones (ceres::GradientChecker) over many random cameras, lenses
// and points, with a numeric step small against each scene (calib/gradient_check_testing.h).
#include "calib/cost_functions.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <ceres/manifold.h>
#include <ceres/product_manifold.h>
#include <ceres/sphere_manifold.h>
#include <gtest/gtest.h>

#include "calib/camera_blocks.h"
#include "calib/gradient_check_testing.h"
#include "simcore/test_scenes.h"

namespace mocap {
namespace {

Camera TestCamera() {
  Camera camera = testing::LookAtCamera(3, Eigen::Vector3d(3000.0, -1500.0, 2500.0), Eigen::Vector3d(0, 0, 900));
  camera.intrinsics.distortion = {-0.21, 0.065, 0.0009, -0.0006, -0.012};
  return camera;
}

// A camera of a capture volume, drawn at random: 2-7 m from a target in the volume, 0.3-3.5 m
// high, a sensor of 640x480 to 2048x1536, lenses from wide (fx 0.5 x width) to long (1.6 x),
// real lenses' distortion (barrel to slight pincushion, small tangential terms).
Camera RandomCamera(uint32_t id, std::mt19937* rng) {
  const auto uniform = [rng](double low, double high) { return std::uniform_real_distribution<double>(low, high)(*rng); };
  const Eigen::Vector3d target(uniform(-1000.0, 1000.0), uniform(-1000.0, 1000.0), uniform(300.0, 1700.0));
  const double azimuth = uniform(0.0, 2.0 * M_PI), range = uniform(2000.0, 7000.0);
  const Eigen::Vector3d centre(target.x() + range * std::cos(azimuth), target.y() + range * std::sin(azimuth),
                               uniform(300.0, 3500.0));
  Camera camera = testing::LookAtCamera(id, centre, target);
  static const int kSensors[][2] = {{640, 480}, {1280, 800}, {1920, 1080}, {2048, 1536}};
  const auto& sensor = kSensors[std::uniform_int_distribution<int>(0, 3)(*rng)];
  CameraIntrinsics& lens = camera.intrinsics;
  lens.width = sensor[0];
  lens.height = sensor[1];
  lens.fx = uniform(0.5, 1.6) * lens.width;
  lens.fy = lens.fx * uniform(0.98, 1.02);
  lens.cx = 0.5 * lens.width + uniform(-30.0, 30.0);
  lens.cy = 0.5 * lens.height + uniform(-30.0, 30.0);
  lens.distortion = {uniform(-0.35, 0.05), uniform(-0.1, 0.2), uniform(-0.002, 0.002), uniform(-0.002, 0.002),
                     uniform(-0.05, 0.05)};
  return camera;
}

// A point the camera sees, 1-7 m deep, anywhere in the image but near its centre lines: there the
// lens terms' derivatives (2xy, r^2 x, ...) vanish, and a relative comparison of a vanishing
// derivative with a numeric one of roundoff says nothing about either.
Eigen::Vector3d RandomPointInCamera(const Camera& camera, std::mt19937* rng) {
  const auto uniform = [rng](double low, double high) { return std::uniform_real_distribution<double>(low, high)(*rng); };
  const auto sign = [rng] { return std::bernoulli_distribution(0.5)(*rng) ? 1.0 : -1.0; };
  const CameraIntrinsics& lens = camera.intrinsics;
  const double x_max = 0.5 * lens.width / lens.fx, y_max = 0.5 * lens.height / lens.fy;
  const double x = sign() * uniform(0.35, 1.0) * x_max, y = sign() * uniform(0.35, 1.0) * y_max;
  return uniform(1000.0, 7000.0) * Eigen::Vector3d(x, y, 1.0);
}

Eigen::Vector3d WorldOf(const Camera& camera, const Eigen::Vector3d& point_in_camera) {
  return camera.rotation.transpose() * (point_in_camera - camera.translation);
}

// How far the first numeric step of the pose moves a point: by its translation (mm) or its
// rotation (rad, times the point's distance from the camera).
double PoseFirstStepMm(const std::array<double, kPoseSize>& pose, const Eigen::Vector3d& point_in_camera) {
  double largest_angle = 0.0, largest_translation = 0.0;
  for (int i = 0; i < 3; ++i) {
    largest_angle = std::max(largest_angle, std::abs(pose[i]));
    largest_translation = std::max(largest_translation, std::abs(pose[3 + i]));
  }
  return std::max(testing::RiddersFirstStep(largest_translation),
                  testing::RiddersFirstStep(largest_angle) * point_in_camera.norm());
}

constexpr int kProbedConfigurations = 2000;

TEST(WandReprojectionErrorTest, ResidualMatchesCameraModel) {
  const Camera camera = TestCamera();
  auto pose = PoseBlock(camera);
  auto intrinsics = IntrinsicsBlock(camera.intrinsics);
  const Eigen::Vector3d centre(150.0, -320.0, 1100.0);
  const Eigen::Vector3d axis = Eigen::Vector3d(0.3, 0.8, -0.2).normalized();
  const double wand[6] = {centre.x(), centre.y(), centre.z(), axis.x(), axis.y(), axis.z()};
  const double offset = 250.0;
  Eigen::Vector2d expected;
  ASSERT_TRUE(camera.ProjectToPixel(centre + offset * axis, &expected));
  const Eigen::Vector2d observed = expected + Eigen::Vector2d(0.7, -1.3);
  std::unique_ptr<ceres::CostFunction> cost(WandReprojectionError::Create(observed, offset));
  const double* parameters[] = {pose.data(), intrinsics.data(), wand};
  double residuals[2];
  ASSERT_TRUE(cost->Evaluate(parameters, residuals, nullptr));
  EXPECT_NEAR(residuals[0], -0.7, 1e-9);
  EXPECT_NEAR(residuals[1], 1.3, 1e-9);
}

// An observation up to 10 px off a projection each way, so that the residual is not zero.
Eigen::Vector2d OffProjection(const Eigen::Vector2d& pixel, std::mt19937* rng) {
  std::uniform_real_distribution<double> off(-10.0, 10.0);
  const double dx = off(*rng);
  return pixel + Eigen::Vector2d(dx, off(*rng));
}

// Random cameras, wands of half-length 100-500 mm on either side of the centre, any direction.
TEST(WandReprojectionErrorTest, GradientsMatchNumericDerivatives) {
  std::mt19937 rng(11);
  ceres::ProductManifold<ceres::EuclideanManifold<3>, ceres::SphereManifold<3>> wand_manifold;
  const std::vector<const ceres::Manifold*> manifolds = {nullptr, nullptr, &wand_manifold};
  for (int k = 0; k < kProbedConfigurations; ++k) {
    const Camera camera = RandomCamera(1, &rng);
    auto pose = PoseBlock(camera);
    auto intrinsics = IntrinsicsBlock(camera.intrinsics);
    const Eigen::Vector3d marker_in_camera = RandomPointInCamera(camera, &rng);
    const Eigen::Vector3d marker = WorldOf(camera, marker_in_camera);
    std::normal_distribution<double> normal;
    const Eigen::Vector3d axis = Eigen::Vector3d(normal(rng), normal(rng), normal(rng)).normalized();
    const double offset = (std::bernoulli_distribution(0.5)(rng) ? 1.0 : -1.0) *
                          std::uniform_real_distribution<double>(100.0, 500.0)(rng);
    const Eigen::Vector3d centre = marker - offset * axis;
    const double wand[6] = {centre.x(), centre.y(), centre.z(), axis.x(), axis.y(), axis.z()};
    Eigen::Vector2d pixel;
    ASSERT_TRUE(camera.ProjectToPixel(marker, &pixel));
    const Eigen::Vector2d observed = OffProjection(pixel, &rng);
    std::unique_ptr<ceres::CostFunction> cost(WandReprojectionError::Create(observed, offset));
    // The centre moves by its own step; the marker by the axis' step (of a unit vector) x offset.
    const double first_step_mm =
        std::max({PoseFirstStepMm(pose, marker_in_camera),
                  testing::RiddersFirstStep(centre.cwiseAbs().maxCoeff()),
                  testing::RiddersFirstStep(1.0) * std::abs(offset)});
    const double* parameters[] = {pose.data(), intrinsics.data(), wand};
    EXPECT_TRUE(testing::GradientsMatchNumeric(*cost, &manifolds, parameters, first_step_mm, marker_in_camera.z(),
                                               "configuration " + std::to_string(k)));
  }
}

TEST(WandReprojectionErrorTest, PointBehindCameraIsRejected) {
  const Camera camera = TestCamera();
  auto pose = PoseBlock(camera);
  auto intrinsics = IntrinsicsBlock(camera.intrinsics);
  // Twice as far behind the camera as the origin is in front of it.
  const Eigen::Vector3d behind = camera.CenterInWorld() * 3.0;
  const double wand[6] = {behind.x(), behind.y(), behind.z(), 1.0, 0.0, 0.0};
  std::unique_ptr<ceres::CostFunction> cost(WandReprojectionError::Create(Eigen::Vector2d(1.0, 1.0), 0.0));
  const double* parameters[] = {pose.data(), intrinsics.data(), wand};
  double residuals[2];
  EXPECT_FALSE(cost->Evaluate(parameters, residuals, nullptr));
}

TEST(KnownPointReprojectionErrorTest, ResidualIsZeroAtTheProjection) {
  const Camera camera = TestCamera();
  auto pose = PoseBlock(camera);
  auto intrinsics = IntrinsicsBlock(camera.intrinsics);
  const Eigen::Vector3d point(300.0, 200.0, 50.0);
  Eigen::Vector2d expected;
  ASSERT_TRUE(camera.ProjectToPixel(point, &expected));
  std::unique_ptr<ceres::CostFunction> cost(KnownPointReprojectionError::Create(point, expected));
  const double* parameters[] = {pose.data(), intrinsics.data()};
  double residuals[2];
  ASSERT_TRUE(cost->Evaluate(parameters, residuals, nullptr));
  EXPECT_NEAR(residuals[0], 0.0, 1e-9);
  EXPECT_NEAR(residuals[1], 0.0, 1e-9);
}

TEST(KnownPointReprojectionErrorTest, GradientsMatchNumericDerivatives) {
  std::mt19937 rng(12);
  for (int k = 0; k < kProbedConfigurations; ++k) {
    const Camera camera = RandomCamera(1, &rng);
    auto pose = PoseBlock(camera);
    auto intrinsics = IntrinsicsBlock(camera.intrinsics);
    const Eigen::Vector3d point_in_camera = RandomPointInCamera(camera, &rng);
    const Eigen::Vector3d point = WorldOf(camera, point_in_camera);
    Eigen::Vector2d pixel;
    ASSERT_TRUE(camera.ProjectToPixel(point, &pixel));
    const Eigen::Vector2d observed = OffProjection(pixel, &rng);
    std::unique_ptr<ceres::CostFunction> cost(KnownPointReprojectionError::Create(point, observed));
    const double* parameters[] = {pose.data(), intrinsics.data()};
    EXPECT_TRUE(testing::GradientsMatchNumeric(*cost, nullptr, parameters, PoseFirstStepMm(pose, point_in_camera),
                                               point_in_camera.z(), "configuration " + std::to_string(k)));
  }
}

}  // namespace
}  // namespace mocap

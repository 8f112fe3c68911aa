// Cost functors: their residuals agree with the shared camera model, and their automatic
// derivatives agree with numeric ones (ceres::GradientChecker), with and without distortion.
#include "calib/cost_functions.h"

#include <memory>
#include <vector>

#include <ceres/gradient_checker.h>
#include <ceres/manifold.h>
#include <ceres/product_manifold.h>
#include <ceres/sphere_manifold.h>
#include <gtest/gtest.h>

#include "calib/camera_blocks.h"
#include "simcore/test_scenes.h"

namespace mocap {
namespace {

Camera TestCamera() {
  Camera camera = testing::LookAtCamera(3, Eigen::Vector3d(3000.0, -1500.0, 2500.0), Eigen::Vector3d(0, 0, 900));
  camera.intrinsics.distortion = {-0.21, 0.065, 0.0009, -0.0006, -0.012};
  return camera;
}

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

TEST(WandReprojectionErrorTest, GradientsMatchNumericDerivatives) {
  const Camera camera = TestCamera();
  auto pose = PoseBlock(camera);
  auto intrinsics = IntrinsicsBlock(camera.intrinsics);
  const Eigen::Vector3d axis = Eigen::Vector3d(-0.5, 0.1, 0.85).normalized();
  const double wand[6] = {-420.0, 610.0, 700.0, axis.x(), axis.y(), axis.z()};
  std::unique_ptr<ceres::CostFunction> cost(WandReprojectionError::Create(Eigen::Vector2d(500.0, 300.0), -250.0));
  ceres::ProductManifold<ceres::EuclideanManifold<3>, ceres::SphereManifold<3>> wand_manifold;
  const std::vector<const ceres::Manifold*> manifolds = {nullptr, nullptr, &wand_manifold};
  ceres::NumericDiffOptions numeric_options;
  ceres::GradientChecker checker(cost.get(), &manifolds, numeric_options);
  ceres::GradientChecker::ProbeResults results;
  const double* parameters[] = {pose.data(), intrinsics.data(), wand};
  EXPECT_TRUE(checker.Probe(parameters, 1e-6, &results)) << results.error_log;
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

TEST(KnownPointReprojectionErrorTest, ResidualAndGradients) {
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
  const std::vector<const ceres::Manifold*>* no_manifolds = nullptr;
  ceres::NumericDiffOptions numeric_options;
  ceres::GradientChecker checker(cost.get(), no_manifolds, numeric_options);
  ceres::GradientChecker::ProbeResults results;
  EXPECT_TRUE(checker.Probe(parameters, 1e-6, &results)) << results.error_log;
}

}  // namespace
}  // namespace mocap

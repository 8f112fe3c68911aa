// Kabsch / Umeyama fits recover known transforms, refuse degenerate input, and never return a
// reflection.
#include "geometry/rigid_fit.h"

#include <random>
#include <stdexcept>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

namespace mocap {
namespace {

std::vector<Eigen::Vector3d> RandomPoints(int n, std::mt19937* rng) {
  std::uniform_real_distribution<double> unit(-1000.0, 1000.0);
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < n; ++i) points.emplace_back(unit(*rng), unit(*rng), unit(*rng));
  return points;
}

TEST(RigidFitTest, RecoversKnownRigidTransformWithNoise) {
  std::mt19937 rng(4);
  std::normal_distribution<double> noise(0.0, 0.5);
  const auto source = RandomPoints(50, &rng);
  const Eigen::Matrix3d rotation =
      Eigen::AngleAxisd(1.1, Eigen::Vector3d(0.2, -0.5, 0.8).normalized()).toRotationMatrix();
  const Eigen::Vector3d translation(120.0, -40.0, 3000.0);
  std::vector<Eigen::Vector3d> target;
  for (const auto& p : source) {
    target.push_back(rotation * p + translation + Eigen::Vector3d(noise(rng), noise(rng), noise(rng)));
  }
  const SimilarityTransform fit = FitRigid(source, target);
  EXPECT_DOUBLE_EQ(fit.scale, 1.0);
  EXPECT_LT(Eigen::AngleAxisd(fit.rotation.transpose() * rotation).angle(), 1e-3);
  EXPECT_LT((fit.translation - translation).norm(), 1.0);
  EXPECT_LT(AlignmentRms(fit, source, target), 1.0);
}

TEST(RigidFitTest, SimilarityRecoversScale) {
  std::mt19937 rng(5);
  const auto source = RandomPoints(10, &rng);
  const Eigen::Matrix3d rotation = Eigen::AngleAxisd(-2.0, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  std::vector<Eigen::Vector3d> target;
  for (const auto& p : source) target.push_back(1.0004 * (rotation * p) + Eigen::Vector3d(1, 2, 3));
  const SimilarityTransform fit = FitSimilarity(source, target);
  EXPECT_NEAR(fit.scale, 1.0004, 1e-12);
  EXPECT_LT(AlignmentRms(fit, source, target), 1e-9);
}

TEST(RigidFitTest, MirroredTargetStillGivesProperRotation) {
  std::mt19937 rng(6);
  const auto source = RandomPoints(8, &rng);
  std::vector<Eigen::Vector3d> target;
  for (const auto& p : source) target.emplace_back(-p.x(), p.y(), p.z());
  const SimilarityTransform fit = FitRigid(source, target);
  EXPECT_NEAR(fit.rotation.determinant(), 1.0, 1e-12);
  EXPECT_GT(AlignmentRms(fit, source, target), 1.0);
}

TEST(RigidFitTest, RejectsDegenerateInput) {
  const std::vector<Eigen::Vector3d> line = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {5, 0, 0}};
  EXPECT_THROW(FitRigid(line, line), std::invalid_argument);
  const std::vector<Eigen::Vector3d> two = {{0, 0, 0}, {1, 0, 0}};
  EXPECT_THROW(FitRigid(two, two), std::invalid_argument);
  const std::vector<Eigen::Vector3d> three = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  EXPECT_THROW(FitRigid(three, two), std::invalid_argument);
}

}  // namespace
}  // namespace mocap

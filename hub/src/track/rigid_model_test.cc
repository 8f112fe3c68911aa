// Rigid-pair links: statistics, breaking non-rigid pairs, predicting a missing marker.
#include "track/rigid_model.h"

#include <random>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

namespace mocap {
namespace {

// Three markers on one rigid body (slots 0-2) and one on another body moving apart (slot 3).
std::vector<Eigen::Vector3d> Pose(double t) {
  const Eigen::Matrix3d r = Eigen::AngleAxisd(t, Eigen::Vector3d(0.3, 1.0, 0.2).normalized()).toRotationMatrix();
  const Eigen::Vector3d centre(100 * t, 50 * std::sin(t), 1000);
  return {centre + r * Eigen::Vector3d(100, 0, 0), centre + r * Eigen::Vector3d(0, 120, 0),
          centre + r * Eigen::Vector3d(0, 0, 90), centre + Eigen::Vector3d(0, 150 + 80 * t, 0)};
}

TEST(RigidModel, KeepsRigidLinksAndBreaksOthers) {
  RigidModel model{RigidModelOptions()};
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, 0.3);
  for (int k = 0; k < 60; ++k) {
    auto pose = Pose(0.05 * k);
    for (auto& p : pose) p += Eigen::Vector3d(noise(rng), noise(rng), noise(rng));
    model.Update({0, 1, 2, 3}, pose);
  }
  const RigidLink* link = model.Link(0, 1);
  ASSERT_NE(link, nullptr);
  EXPECT_FALSE(link->broken);
  EXPECT_EQ(link->samples, 60);
  EXPECT_NEAR(link->mean, std::hypot(100.0, 120.0), 0.3);
  EXPECT_LT(std::sqrt(link->Variance()), 1.0);
  ASSERT_NE(model.Link(2, 3), nullptr);
  EXPECT_TRUE(model.Link(2, 3)->broken);  // slot 3 drifts 80 mm/s away
  EXPECT_EQ(model.NumActiveLinks(), 3);
  model.ResetSlot(1);
  EXPECT_EQ(model.Link(0, 1), nullptr);
}

TEST(RigidModel, PredictsMissingMarkerFromLinkedOnes) {
  RigidModelOptions options;
  RigidModel model(options);
  for (int k = 0; k < 40; ++k) model.Update({0, 1, 2}, {Pose(0.05 * k)[0], Pose(0.05 * k)[1], Pose(0.05 * k)[2]});
  const auto truth = Pose(2.5);
  std::vector<char> measured = {0, 1, 1};
  std::vector<Eigen::Vector3d> positions = {Eigen::Vector3d::Zero(), truth[1], truth[2]};
  // Two links: the point on the spheres' circle nearest to a prior 15 mm off.
  Eigen::Vector3d predicted;
  ASSERT_TRUE(model.Predict(0, truth[0] + Eigen::Vector3d(10, -10, 5), measured, positions, &predicted));
  EXPECT_NEAR((predicted - truth[1]).norm(), model.Link(0, 1)->mean, 0.05);
  EXPECT_NEAR((predicted - truth[2]).norm(), model.Link(0, 2)->mean, 0.05);
  EXPECT_LT((predicted - truth[0]).norm(), 15.0);
  // One link is below min_links_used = 2: no prediction.
  measured = {0, 1, 0};
  EXPECT_FALSE(model.Predict(0, truth[0], measured, positions, &predicted));
}

TEST(RigidModel, ThreeLinksPinThePoint) {
  RigidModel model{RigidModelOptions()};
  // A fourth marker rigid with the three others, off their plane (in the plane the two
  // intersections of three spheres coincide and the depth is ill-conditioned).
  const auto with_fourth = [](double t) {
    auto pose = Pose(t);
    const Eigen::Vector3d normal = (pose[1] - pose[0]).cross(pose[2] - pose[0]).normalized();
    pose[3] = 0.5 * (pose[0] + pose[1]) + 0.8 * (pose[2] - pose[0]) + 60.0 * normal;
    return pose;
  };
  for (int k = 0; k < 40; ++k) model.Update({0, 1, 2, 3}, with_fourth(0.05 * k));
  const auto truth = with_fourth(3.0);
  Eigen::Vector3d predicted;
  ASSERT_TRUE(model.Predict(3, truth[3] + Eigen::Vector3d(4, 4, -4), {1, 1, 1, 0}, truth, &predicted));
  EXPECT_LT((predicted - truth[3]).norm(), 1.0);
}

}  // namespace
}  // namespace mocap

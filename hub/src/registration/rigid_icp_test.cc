// Rigid ICP: recovers a known motion from far starts (the principal-axis starts matter), ignores
// outliers beyond the pair distance, refines point-to-plane on a surface, and its k-d tree agrees
// with a scan of every point.
#include "registration/rigid_icp.h"

#include <random>
#include <stdexcept>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

namespace mocap {
namespace {

std::vector<Eigen::Vector3d> RandomCloud(size_t count, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> x(-300, 300), y(-150, 150), z(-60, 60);  // three distinct spreads
  std::vector<Eigen::Vector3d> cloud;
  for (size_t i = 0; i < count; ++i) cloud.emplace_back(x(rng), y(rng), z(rng));
  return cloud;
}

SimilarityTransform Motion(double angle_deg, const Eigen::Vector3d& axis, const Eigen::Vector3d& shift) {
  SimilarityTransform motion;
  motion.rotation = Eigen::AngleAxisd(angle_deg * M_PI / 180.0, axis.normalized()).toRotationMatrix();
  motion.translation = shift;
  return motion;
}

std::vector<Eigen::Vector3d> Moved(const std::vector<Eigen::Vector3d>& cloud, const SimilarityTransform& motion) {
  std::vector<Eigen::Vector3d> out;
  for (const Eigen::Vector3d& p : cloud) out.push_back(motion.Apply(p));
  return out;
}

TEST(RigidIcp, RecoversAKnownMotionFromFarStarts) {
  const std::vector<Eigen::Vector3d> source = RandomCloud(200, 1);
  for (double angle : {10.0, 60.0, 150.0}) {
    const SimilarityTransform truth = Motion(angle, Eigen::Vector3d(0.3, -1, 0.5), Eigen::Vector3d(400, -50, 900));
    const RigidIcpResult result = AlignRigidIcp(source, Moved(source, truth), RigidIcpOptions{});
    EXPECT_LT(result.rms_mm, 1e-6) << angle;
    EXPECT_LT((result.target_from_source.rotation - truth.rotation).norm(), 1e-8) << angle;
    EXPECT_LT((result.target_from_source.translation - truth.translation).norm(), 1e-6) << angle;
  }
  // From the identity alone a half turn is out of reach: the starts are what found it above.
  RigidIcpOptions identity_only;
  identity_only.principal_axis_starts = false;
  const SimilarityTransform half_turn = Motion(150.0, Eigen::Vector3d(0.3, -1, 0.5), Eigen::Vector3d(400, -50, 900));
  EXPECT_GT(AlignRigidIcp(source, Moved(source, half_turn), identity_only).rms_mm, 1.0);
}

TEST(RigidIcp, PairsBeyondTheDistanceAreLeftOut) {
  const std::vector<Eigen::Vector3d> target = RandomCloud(3000, 3);
  const SimilarityTransform truth = Motion(5.0, Eigen::Vector3d(0, 0, 1), Eigen::Vector3d(15, -10, 5));
  SimilarityTransform source_from_target;
  source_from_target.rotation = truth.rotation.transpose();
  source_from_target.translation = -(source_from_target.rotation * truth.translation);
  std::vector<Eigen::Vector3d> source;
  for (size_t i = 0; i < 300; ++i) source.push_back(source_from_target.Apply(target[i * 10]));
  // Five stray points 500 mm beyond the cloud: kept, they would pull the fit off.
  for (int i = 0; i < 5; ++i) source.emplace_back(800.0 + 20 * i, 0, 0);
  RigidIcpOptions options;
  options.max_pair_distance_mm = 30.0;
  const RigidIcpResult result = AlignRigidIcp(source, target, options);
  EXPECT_EQ(result.pairs, 300u);
  EXPECT_LT(result.rms_mm, 1e-6);
  EXPECT_LT((result.target_from_source.rotation - truth.rotation).norm(), 1e-8);
  EXPECT_GT(AlignRigidIcp(source, target, RigidIcpOptions{}).rms_mm, 1.0);
}

TEST(RigidIcp, PointToPlaneFindsAPoseNearestVerticesCannot) {
  // A finely sampled wavy sheet with normals; the source: points of the same surface between
  // its samples (as markers lie between a mesh's vertices), seen from another frame.
  std::vector<Eigen::Vector3d> sheet, normals, source;
  const auto height = [](double x, double y) { return 20 * std::sin(x / 40) * std::cos(y / 55) + 0.001 * x * x; };
  for (double x = -150; x <= 150; x += 3)
    for (double y = -100; y <= 100; y += 3) {
      sheet.emplace_back(x, y, height(x, y));
      const double dx = 0.5 * std::cos(x / 40) * std::cos(y / 55) + 0.002 * x;
      const double dy = -20.0 / 55 * std::sin(x / 40) * std::sin(y / 55);
      normals.push_back(Eigen::Vector3d(-dx, -dy, 1).normalized());
    }
  const SimilarityTransform truth = Motion(12.0, Eigen::Vector3d(0.2, 1, 0.3), Eigen::Vector3d(40, -30, 25));
  SimilarityTransform source_from_target;
  source_from_target.rotation = truth.rotation.transpose();
  source_from_target.translation = -(source_from_target.rotation * truth.translation);
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> x(-130, 130), y(-85, 85);
  for (int i = 0; i < 50; ++i) {
    const double px = x(rng), py = y(rng);
    source.push_back(source_from_target.Apply(Eigen::Vector3d(px, py, height(px, py))));
  }
  const RigidIcpResult plane = AlignRigidIcp(source, sheet, RigidIcpOptions{}, &normals);
  const RigidIcpResult point = AlignRigidIcp(source, sheet, RigidIcpOptions{});
  const double plane_error = (plane.target_from_source.rotation - truth.rotation).norm();
  EXPECT_LT(plane_error, 2e-3);
  EXPECT_LT(plane_error, 0.5 * (point.target_from_source.rotation - truth.rotation).norm());
  EXPECT_LT(plane.rms_mm, 0.1);
  const std::vector<Eigen::Vector3d> too_few(3);
  EXPECT_THROW(AlignRigidIcp(source, sheet, RigidIcpOptions{}, &too_few), std::invalid_argument);
}

TEST(RigidIcp, NearestPointsAgreesWithAScan) {
  const std::vector<Eigen::Vector3d> cloud = RandomCloud(500, 3);
  const NearestPoints nearest(cloud);
  for (const Eigen::Vector3d& query : RandomCloud(200, 4)) {
    size_t best = 0;
    for (size_t i = 1; i < cloud.size(); ++i)
      if ((cloud[i] - query).squaredNorm() < (cloud[best] - query).squaredNorm()) best = i;
    double squared = 0.0;
    EXPECT_EQ(nearest.Nearest(query, &squared), best);
    EXPECT_NEAR(squared, (cloud[best] - query).squaredNorm(), 1e-9);
  }
}

TEST(RigidIcp, RefusesTooFewPointsAndBadOptions) {
  const std::vector<Eigen::Vector3d> two = {Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones()};
  EXPECT_THROW(AlignRigidIcp(two, RandomCloud(10, 5), RigidIcpOptions{}), std::invalid_argument);
  RigidIcpOptions options;
  options.max_iterations = 0;
  EXPECT_THROW(options.Check(), std::invalid_argument);
  options = {};
  options.max_pair_distance_mm = -1.0;
  EXPECT_THROW(options.Check(), std::invalid_argument);
}

}  // namespace
}  // namespace mocap

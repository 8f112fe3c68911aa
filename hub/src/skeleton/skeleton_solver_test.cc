// The per-frame solve on simulated subjects with exact markers: the true angles come back (the
// Jacobians, bounds and warm start all have to be right for that); missing markers are simply
// absent; one marker thrown far off does not drag the pose (the robust loss); Euler angles from a
// rotation for every axis order.
#include "skeleton/skeleton_solver.h"

#include <random>

#include <gtest/gtest.h>

#include "skeleton/kinematics.h"
#include "skeleton/skeleton_sim.h"
#include "skeleton/skeleton_testing.h"

namespace mocap {
namespace {

double MaxJointErrorDeg(const Skeleton& s, const std::vector<double>& a, const std::vector<double>& b) {
  double worst = 0.0;
  for (size_t k = 3 + s.segments[0].dofs.size(); k < a.size(); ++k)
    worst = std::max(worst, std::fabs(std::remainder(a[k] - b[k], 2 * M_PI)) * 180.0 / M_PI);
  return worst;
}

SkeletonSimulation Gait(double wobble) {
  SkeletonSimOptions options;
  options.motion = SkeletonSimMotion::kGait;
  options.duration_s = 1.0;
  options.wobble_mm = wobble;
  return SimulateSkeleton(TwentySegmentTemplate(), options);
}

std::vector<Eigen::Vector3d> Frame(const SkeletonSimulation& sim, size_t f) {
  std::vector<Eigen::Vector3d> points;
  for (size_t m = 0; m < sim.markers.NumMarkers(); ++m) points.push_back(sim.markers.At(f, m));
  return points;
}

TEST(SkeletonSolver, RecoversTrueAnglesFromExactMarkers) {
  const SkeletonSimulation sim = Gait(0.0);
  SkeletonSolver solver(sim.subject, SkeletonSolveOptions{});
  for (size_t f = 0; f < sim.markers.NumFrames(); ++f) {
    const SkeletonFrameFit fit = solver.Solve(Frame(sim, f));
    ASSERT_TRUE(fit.solved) << f;
    EXPECT_LT(fit.rms_mm, 0.05) << f;
    EXPECT_LT(MaxJointErrorDeg(sim.subject, fit.pose, sim.motion.poses[f]), 0.05) << f;
  }
}

TEST(SkeletonSolver, MissingMarkersAreAbsentAndOutliersDoNotDrag) {
  const SkeletonSimulation sim = Gait(0.0);
  SkeletonSolver solver(sim.subject, SkeletonSolveOptions{});
  // Markers of segments with 3 or more: the others left determine the segment still.
  std::vector<size_t> candidates;
  for (size_t m = 0; m < sim.subject.markers.size(); ++m) {
    int on_segment = 0;
    for (const SkeletonMarker& other : sim.subject.markers) on_segment += other.segment == sim.subject.markers[m].segment;
    if (on_segment >= 3) candidates.push_back(m);
  }
  std::mt19937 rng(5);
  for (size_t f = 0; f < sim.markers.NumFrames(); ++f) {
    std::vector<Eigen::Vector3d> points = Frame(sim, f);
    const size_t gone = candidates[rng() % candidates.size()];
    const size_t wild = candidates[rng() % candidates.size()];
    if (sim.subject.markers[wild].segment == sim.subject.markers[gone].segment) continue;
    points[gone] = MarkerTrajectories::Gap();
    points[wild] += Eigen::Vector3d(150, -80, 60);
    const SkeletonFrameFit fit = solver.Solve(points);
    ASSERT_TRUE(fit.solved);
    EXPECT_TRUE(std::isnan(fit.residual_mm[gone]));
    EXPECT_EQ(fit.markers, static_cast<int>(points.size()) - 1);
    EXPECT_GT(fit.residual_mm[wild], 120.0);  // left where it is (180 mm off), not fitted
    EXPECT_LT(MaxJointErrorDeg(sim.subject, fit.pose, sim.motion.poses[f]), 2.0) << f;
  }
}

TEST(SkeletonSolver, TooFewMarkersIsNotSolved) {
  const SkeletonSimulation sim = Gait(0.0);
  SkeletonSolver solver(sim.subject, SkeletonSolveOptions{});
  std::vector<Eigen::Vector3d> points(sim.markers.NumMarkers(), MarkerTrajectories::Gap());
  for (int m = 0; m < 3; ++m) points[m] = sim.markers.At(0, m);
  EXPECT_FALSE(solver.Solve(points).solved);
  EXPECT_THROW(solver.Solve({}), std::invalid_argument);
}

TEST(SkeletonSolver, EulerAnglesForEveryOrder) {
  const int orders[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  for (const auto& o : orders) {
    const Eigen::Vector3d angles(0.3, -0.7, 1.9);
    const Eigen::Matrix3d r = AxisRotation(o[0], angles[0]) * AxisRotation(o[1], angles[1]) * AxisRotation(o[2], angles[2]);
    const Eigen::Vector3d back = EulerFromRotation(r, o[0], o[1], o[2]);
    EXPECT_TRUE(back.isApprox(angles, 1e-9)) << o[0] << o[1] << o[2] << ": " << back.transpose();
  }
}

}  // namespace
}  // namespace mocap

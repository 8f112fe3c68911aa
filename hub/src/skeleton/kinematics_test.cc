// Forward kinematics: a marker's derivative by each pose parameter (central differences) is what
// the solvers' analytic Jacobians use: the translation itself, axis x (marker - joint centre) per
// radian for every rotation above the marker, nothing for the others.
#include "skeleton/kinematics.h"

#include <random>

#include <Eigen/Geometry>

#include <gtest/gtest.h>

#include "skeleton/skeleton_template.h"

namespace mocap {
namespace {

TEST(Kinematics, DerivativesMatchAxisCrossArm) {
  std::vector<std::string> unplaced;
  const Skeleton s = SkeletonTemplateFromNames(
      {"LFWT", "RFWT", "LBWT", "RBWT", "LTHI", "LKNE", "LSHN", "LANK", "LHEE", "LTOE", "LMT5", "C7", "CLAV", "STRN",
       "T10", "LSHO", "LUPA", "LELB", "LFRM", "LWRA", "LWRB", "LFIN", "LFHD", "RFHD", "LBHD"},
      &unplaced);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> angle(-0.8, 0.8);
  std::vector<double> pose(s.NumPoseParameters());
  for (double& p : pose) p = angle(rng);
  pose[0] = 100;
  pose[1] = 900;
  pose[2] = -50;
  SkeletonPoseState state, plus, minus;
  ForwardKinematics(s, pose.data(), nullptr, &state);
  const auto chains = SegmentChains(s);
  for (const SkeletonMarker& m : s.markers) {
    const Eigen::Vector3d p = MarkerInSkeleton(state, m.segment, m.offset);
    for (size_t k = 0; k < pose.size(); ++k) {
      std::vector<double> a = pose, b = pose;
      a[k] += 1e-6;
      b[k] -= 1e-6;
      ForwardKinematics(s, a.data(), nullptr, &plus);
      ForwardKinematics(s, b.data(), nullptr, &minus);
      const Eigen::Vector3d numeric =
          (MarkerInSkeleton(plus, m.segment, m.offset) - MarkerInSkeleton(minus, m.segment, m.offset)) / 2e-6;
      Eigen::Vector3d analytic = Eigen::Vector3d::Zero();
      if (k < 3) {
        analytic[k] = 1.0;
      } else {
        const int g = state.dof_segment[k];
        bool above = false;
        for (int c : chains[m.segment]) above = above || c == g;
        if (above) analytic = state.axis[k].cross(p - state.origin[g]);
      }
      EXPECT_LT((numeric - analytic).norm(), 1e-4) << m.name << " parameter " << k;
    }
  }
}

TEST(Kinematics, RestPoseFramesAreParallelAndOffsetsAdd) {
  std::vector<std::string> unplaced;
  const Skeleton s = SkeletonTemplateFromNames({"LFWT", "RFWT", "LBWT", "LTHI", "LKNE", "LANK", "LHEE"}, &unplaced);
  std::vector<double> pose(s.NumPoseParameters(), 0.0);
  SkeletonPoseState state;
  ForwardKinematics(s, pose.data(), nullptr, &state);
  for (size_t g = 1; g < s.NumSegments(); ++g) {
    EXPECT_TRUE(state.rotation[g].isIdentity(1e-12));
    EXPECT_TRUE(state.origin[g].isApprox(state.origin[s.segments[g].parent] + s.segments[g].offset));
  }
}

TEST(Kinematics, BoundsFollowLimitsExceptTheRoot) {
  std::vector<std::string> unplaced;
  const Skeleton s = SkeletonTemplateFromNames({"LFWT", "RFWT", "LBWT", "LTHI", "LKNE", "LANK"}, &unplaced);
  std::vector<double> lower, upper;
  PoseBounds(s, &lower, &upper);
  for (size_t k = 0; k < 6; ++k) EXPECT_TRUE(std::isinf(lower[k]) && std::isinf(upper[k]));
  const int knee = s.FindSegment("LeftLeg");
  ASSERT_GE(knee, 0);
  EXPECT_NEAR(upper[s.FirstDof(knee)], s.segments[knee].dofs[0].max_deg * M_PI / 180.0, 1e-12);
}

}  // namespace
}  // namespace mocap

// Joint-angle and length errors: zero against itself, a known offset where one is added, and
// unsolved frames left out.
#include "skeleton/skeleton_eval.h"

#include <gtest/gtest.h>

#include "skeleton/skeleton_sim.h"
#include "skeleton/skeleton_testing.h"

namespace mocap {
namespace {

TEST(SkeletonEval, KnownErrors) {
  SkeletonSimOptions options;
  options.duration_s = 0.5;
  const SkeletonSimulation sim = SimulateSkeleton(TwentySegmentTemplate(), options);
  const SkeletonEvalReport same = EvaluateSkeleton(sim.subject, sim.motion, sim.subject, sim.motion);
  for (const auto& j : same.joints) EXPECT_EQ(j.rms_deg, 0.0);
  Skeleton longer = sim.subject;
  const int knee = longer.FindSegment("LeftLeg");
  longer.segments[knee].offset *= 1.01;
  SkeletonMotion off = sim.motion;
  const size_t k = longer.FirstDof(knee);
  for (auto& pose : off.poses) pose[k] += 2.0 * M_PI / 180.0;
  off.poses[0].clear();
  const SkeletonEvalReport r = EvaluateSkeleton(sim.subject, sim.motion, longer, off);
  for (size_t i = 0; i < r.joints.size(); ++i) {
    const bool is_knee = r.joints[i].segment == "LeftLeg";
    EXPECT_NEAR(r.joints[i].rms_deg, is_knee ? 2.0 : 0.0, 1e-9) << r.joints[i].segment;
    EXPECT_EQ(r.joints[i].frames, sim.motion.poses.size() - 1);
    EXPECT_NEAR(r.lengths[i].error_mm, is_knee ? 0.01 * r.lengths[i].truth_mm : 0.0, 1e-9);
  }
  Skeleton other = sim.subject;
  other.segments[2].name = "Renamed";
  EXPECT_THROW(EvaluateSkeleton(sim.subject, sim.motion, other, sim.motion), std::invalid_argument);
}

}  // namespace
}  // namespace mocap

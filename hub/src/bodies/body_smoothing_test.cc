// Orientation refinement over neighbouring frames: on a body spinning at a steady rate it cuts
// the per-frame rotation noise (a centred parabola through 13 frames: to 0.42 of it), it
// leaves a sudden turn as measured (where a plain line would be off by a degree), it keeps the
// measured marker centroid, and it leaves alone what it must (noiseless fits, predicted frames,
// half window 0).
#include <cmath>
#include <cstdio>
#include <random>
#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "bodies/body_smoothing.h"
#include "bodies/body_test_sequence.h"

namespace mocap {
namespace {

using namespace body_test;  // NOLINT: test helpers

TEST(BodySmoothing, CutsTheNoiseOfASteadySpin) {
  const RigidBodyDefinition body = Wand();
  Sequence s = Simulate(body, 3000, 0.35, Spinning);
  std::vector<double> before, after;
  for (size_t f = 0; f < s.poses.size(); ++f) before.push_back(ErrorDeg(s.poses[f], s.truth[f]));
  const BodySmoothingStats stats = SmoothBodyPoses(body, s.markers, &s.poses);
  for (size_t f = 0; f < s.poses.size(); ++f) after.push_back(ErrorDeg(s.poses[f], s.truth[f]));
  // The residuals tell the noise: a rigid fit of 4 points keeps 6 of their 12 degrees of freedom.
  EXPECT_NEAR(stats.noise_mm, 0.35, 0.035);
  // A steady spin fits the model: at p = 0.001, a handful of windows fail by chance.
  EXPECT_GE(stats.refined, 2950u);
  // A centred parabola through 13 equally good frames has 0.175 of one frame's variance (0.42 of
  // its error: the root of the sum of its squared least-squares weights at t = 0); 3000 frames pin
  // the medians to a few per cent (neighbouring refined frames share their errors).
  std::printf("steady spin: median %.3f deg per frame, %.3f refined (%zu of 3000 over the full window)\n",
              Median(before), Median(after), stats.refined);
  EXPECT_LT(Median(after), 0.55 * Median(before));
  EXPECT_GT(Median(after), 0.35 * Median(before));
}

TEST(BodySmoothing, KeepsTheMeasuredCentroidAndPivot) {
  const RigidBodyDefinition body = Wand();
  Sequence s = Simulate(body, 50, 0.3, Spinning);
  SmoothBodyPoses(body, s.markers, &s.poses);
  for (size_t f = 0; f < s.poses.size(); ++f) {
    Eigen::Vector3d in_body = Eigen::Vector3d::Zero(), in_world = Eigen::Vector3d::Zero();
    for (size_t i = 0; i < body.markers.size(); ++i) in_body += s.markers[f].in_body[i], in_world += s.markers[f].in_world[i];
    in_body /= 4.0, in_world /= 4.0;
    const Eigen::Matrix3d r = s.poses[f].orientation.toRotationMatrix();
    EXPECT_LT((r * in_body + s.poses[f].position - in_world).norm(), 1e-9);
    EXPECT_LT((r * body.pivot + s.poses[f].position - s.poses[f].pivot).norm(), 1e-9);
  }
}

// The angular velocity turns round at frame 100 (a knock): 3 deg per frame about z, then about x
// the other way. A centred parabola through frames 94-106 would put frame 100 off by 2.5 deg
// (1.76 deg about z and about x, its weights applied to the V-shaped turn); the test must see that
// and keep the frames near the knock as measured (their noise: about 0.02 deg).
TEST(BodySmoothing, LeavesASuddenTurnAsMeasured) {
  const RigidBodyDefinition body = Wand();
  const auto knock = [](int f) -> Eigen::Matrix3d {
    const Eigen::Matrix3d at_knock = Eigen::AngleAxisd(3.0 * kDeg * 100, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    if (f <= 100) return Eigen::AngleAxisd(3.0 * kDeg * f, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    return Eigen::AngleAxisd(-3.0 * kDeg * (f - 100), Eigen::Vector3d::UnitX()).toRotationMatrix() * at_knock;
  };
  Sequence s = Simulate(body, 200, 0.02, knock);
  const BodySmoothingStats stats = SmoothBodyPoses(body, s.markers, &s.poses);
  EXPECT_GE(stats.shrunk + stats.unchanged, 2u);  // frames 99 and 101 at least
  for (int f = 95; f <= 105; ++f)
    EXPECT_LT(ErrorDeg(s.poses[static_cast<size_t>(f)], s.truth[static_cast<size_t>(f)]), 0.1) << f;
}

TEST(BodySmoothing, LeavesAloneWhatItMust) {
  const RigidBodyDefinition body = Wand();
  // Noiseless fits: nothing to average, poses exact already.
  Sequence exact = Simulate(body, 20, 0.0, Spinning);
  const BodySmoothingStats stats = SmoothBodyPoses(body, exact.markers, &exact.poses);
  EXPECT_EQ(stats.refined + stats.shrunk, 0u);
  EXPECT_EQ(stats.unchanged, 20u);
  for (size_t f = 0; f < exact.poses.size(); ++f) EXPECT_LT(ErrorDeg(exact.poses[f], exact.truth[f]), 1e-6);

  // Predicted frames and half window 0.
  Sequence s = Simulate(body, 30, 0.3, Spinning);
  s.poses[10].tracked = false;
  s.poses[10].predicted = true;
  const Sequence before = s;
  SmoothBodyPoses(body, s.markers, &s.poses);
  EXPECT_TRUE(s.poses[10].orientation.isApprox(before.poses[10].orientation));
  EXPECT_TRUE(s.poses[10].position.isApprox(before.poses[10].position));
  EXPECT_FALSE(s.poses[11].orientation.isApprox(before.poses[11].orientation, 1e-9));
  Sequence off = before;
  BodySmoothingOptions none;
  none.half_window = 0;
  SmoothBodyPoses(body, off.markers, &off.poses, none);
  for (size_t f = 0; f < off.poses.size(); ++f) EXPECT_TRUE(off.poses[f].orientation.isApprox(before.poses[f].orientation));
}

TEST(BodySmoothing, RefusesBadOptions) {
  BodySmoothingOptions bad;
  bad.half_window = -1;
  EXPECT_THROW(bad.Check(), std::invalid_argument);
  bad = {};
  bad.test_z = 0.0;
  EXPECT_THROW(bad.Check(), std::invalid_argument);
  const RigidBodyDefinition body = Wand();
  Sequence s = Simulate(body, 5, 0.3, Spinning);
  s.markers.pop_back();
  EXPECT_THROW(SmoothBodyPoses(body, s.markers, &s.poses), std::invalid_argument);
}

}  // namespace
}  // namespace mocap

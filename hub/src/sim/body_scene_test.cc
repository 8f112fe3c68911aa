// Rigid bodies around a motion: the markers ride the true poses rigidly, the paths turn fast and
// bring the bodies close to each other, and bad input is refused.
#include <cmath>
#include <stdexcept>

#include <gtest/gtest.h>

#include "sim/body_scene.h"
#include "simcore/synthetic_motion.h"

namespace mocap {
namespace {

std::vector<RigidBodyDefinition> ThreeBodies() {
  RigidBodyDefinition a{"a", {{0, 0, 0}, {110, 0, 0}, {30, 75, 0}, {45, 20, 60}}, Eigen::Vector3d::Zero()};
  RigidBodyDefinition b{"b", {{0, 0, 0}, {95, 10, 0}, {20, 115, 5}, {70, 60, -40}, {-35, 50, 25}}, Eigen::Vector3d(10, 10, 10)};
  RigidBodyDefinition c{"c", {{0, 0, 0}, {60, 0, 0}, {0, 40, 0}, {85, 55, 20}, {30, 90, 45}, {-20, 35, 70}}, Eigen::Vector3d::Zero()};
  return {a, b, c};
}

TEST(BodyScene, MarkersRideTheTruePoses) {
  SyntheticMotionOptions walk;
  walk.markers = 12;
  walk.frames = 300;
  walk.rate_hz = 100.0;
  const MarkerTrajectories motion = MakeSyntheticMotion(walk);
  const std::vector<RigidBodyDefinition> bodies = ThreeBodies();
  const BodyScene scene = AddRigidBodies(motion, bodies);
  ASSERT_EQ(scene.scene.NumMarkers(), 12u + 4 + 5 + 6);
  EXPECT_EQ(scene.scene.names[12], "a:1");
  EXPECT_EQ(scene.scene.names.back(), "c:6");
  ASSERT_EQ(scene.poses.size(), 300u);
  double closest = 1e9, fastest_deg = 0.0;
  for (size_t f = 0; f < 300; ++f) {
    size_t column = 12;
    for (size_t b = 0; b < bodies.size(); ++b) {
      const BodyPose& pose = scene.poses[f].poses[b];
      const Eigen::Matrix3d r = pose.orientation.toRotationMatrix();
      for (const Eigen::Vector3d& m : bodies[b].markers)
        ASSERT_LT((scene.scene.At(f, column++) - (r * m + pose.position)).norm(), 1e-6);
      EXPECT_LT((pose.pivot - (r * bodies[b].pivot + pose.position)).norm(), 1e-6);
      if (f > 0)
        fastest_deg = std::max(fastest_deg, pose.orientation.angularDistance(scene.poses[f - 1].poses[b].orientation) *
                                                180.0 / 3.14159265358979323846 * 100.0);
    }
    for (size_t b = 0; b < 3; ++b)
      for (size_t c = b + 1; c < 3; ++c)
        closest = std::min(closest, (scene.poses[f].poses[b].position - scene.poses[f].poses[c].position).norm());
    for (size_t m = 0; m < 12; ++m) EXPECT_EQ(scene.scene.At(f, m), motion.At(f, m));
  }
  EXPECT_LT(closest, 250.0);       // the bodies pass close to each other
  EXPECT_GT(fastest_deg, 200.0);   // and spin fast (degrees per second)
}

TEST(BodyScene, RefusesBadInput) {
  SyntheticMotionOptions walk;
  walk.markers = 12;
  const MarkerTrajectories motion = MakeSyntheticMotion(walk);
  EXPECT_THROW(AddRigidBodies(motion, {}), std::invalid_argument);
  EXPECT_THROW(AddRigidBodies(MarkerTrajectories{}, ThreeBodies()), std::invalid_argument);
  BodySceneOptions bad;
  bad.max_radius_mm = 10.0;
  EXPECT_THROW(AddRigidBodies(motion, ThreeBodies(), bad), std::invalid_argument);
}

}  // namespace
}  // namespace mocap

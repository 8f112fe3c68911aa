// Rigid-cluster permutation repair: a cluster whose points were permuted gets them back; a right
// assignment, and a pair with nothing but its own distance, are left alone.
#include "track/rigid_swaps.h"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

namespace mocap {
namespace {

// A plate turning fast: a triangle 19 / 28 / 38 mm (slots 0-2) and a fourth marker 50 mm off it
// (slot 3), all rigid; slot 4 is another body's marker, far away.
std::vector<Eigen::Vector3d> Plate(double t) {
  const Eigen::Matrix3d r = Eigen::AngleAxisd(3.0 * t, Eigen::Vector3d(0.2, 0.4, 1.0).normalized()).toRotationMatrix();
  const Eigen::Vector3d centre(200 * t, 0, 1000);
  return {centre, centre + r * Eigen::Vector3d(19, 0, 0), centre + r * Eigen::Vector3d(-8, 27, 0),
          centre + r * Eigen::Vector3d(10, 10, 48), Eigen::Vector3d(900, 400 * t, 1200)};
}

class RigidSwaps : public ::testing::Test {
 protected:
  RigidSwaps() : model_(RigidModelOptions()) {
    for (int k = 0; k < 30; ++k) model_.Update({0, 1, 2, 3, 4}, Plate(0.02 * k));
  }

  // Resolves with slot s holding point held[s] of the plate at time 1.0 (then the `extra` points).
  int Resolve(const std::vector<int>& held, std::vector<int>* point_of_slot, std::vector<char>* changed,
              const std::vector<Eigen::Vector3d>& extra = {}) {
    points_.clear();
    std::vector<Eigen::Vector3d> positions = Plate(1.0);
    positions.insert(positions.end(), extra.begin(), extra.end());
    for (const Eigen::Vector3d& p : positions) {
      ReconstructedPoint point;
      point.point_in_world = p;
      points_.push_back(point);
    }
    *point_of_slot = held;
    changed->assign(held.size(), 0);
    RigidSwapResolver resolver{RigidSwapOptions()};
    return resolver.Resolve(model_, std::vector<char>(held.size(), 1), points_, point_of_slot, changed);
  }

  RigidModel model_;
  std::vector<ReconstructedPoint> points_;
};

TEST_F(RigidSwaps, SwappedPairComesBack) {
  std::vector<int> point_of_slot;
  std::vector<char> changed;
  EXPECT_EQ(Resolve({1, 0, 2, 3, 4}, &point_of_slot, &changed), 1);
  EXPECT_EQ(point_of_slot, (std::vector<int>{0, 1, 2, 3, 4}));
  EXPECT_EQ(changed, (std::vector<char>{1, 1, 0, 0, 0}));
}

TEST_F(RigidSwaps, RotatedTriangleComesBack) {
  std::vector<int> point_of_slot;
  std::vector<char> changed;
  EXPECT_EQ(Resolve({2, 0, 1, 3, 4}, &point_of_slot, &changed), 1);
  EXPECT_EQ(point_of_slot, (std::vector<int>{0, 1, 2, 3, 4}));
  EXPECT_EQ(changed, (std::vector<char>{1, 1, 1, 0, 0}));
}

TEST_F(RigidSwaps, RightAssignmentAndMissingPointsAreLeftAlone) {
  std::vector<int> point_of_slot;
  std::vector<char> changed;
  EXPECT_EQ(Resolve({0, 1, 2, 3, 4}, &point_of_slot, &changed), 0);
  EXPECT_EQ(changed, std::vector<char>(5, 0));
  // Only two plate markers hold points: their one mutual distance cannot tell them apart.
  EXPECT_EQ(Resolve({1, 0, -1, -1, 4}, &point_of_slot, &changed), 0);
  EXPECT_EQ(point_of_slot, (std::vector<int>{1, 0, -1, -1, 4}));
}

// The plate traded a marker with a neighbour: the far marker's track (slot 4) holds plate
// point 0, and slot 0 holds a stray point 20 mm beside the plate. No order of the plate's own
// points fits, so the plate is gathered again from the points around it: slot 0 takes its point
// back, slot 4 loses it, the stray point is left to nobody.
TEST_F(RigidSwaps, ClusterTradedWithANeighbourIsGatheredAgain) {
  const Eigen::Vector3d stray = Plate(1.0)[0] + Eigen::Vector3d(0, 0, -20);
  std::vector<int> point_of_slot;
  std::vector<char> changed;
  EXPECT_EQ(Resolve({5, 1, 2, 3, 0}, &point_of_slot, &changed, {stray}), 1);
  EXPECT_EQ(point_of_slot, (std::vector<int>{0, 1, 2, 3, -1}));
  EXPECT_EQ(changed, (std::vector<char>{1, 0, 0, 0, 0}));
  // Off: the plate keeps the stray point.
  RigidSwapOptions off;
  off.regather = false;
  point_of_slot = {5, 1, 2, 3, 0};
  changed.assign(5, 0);
  RigidSwapResolver resolver{off};
  EXPECT_EQ(resolver.Resolve(model_, std::vector<char>(5, 1), points_, &point_of_slot, &changed), 0);
  EXPECT_EQ(point_of_slot, (std::vector<int>{5, 1, 2, 3, 0}));
}

TEST(RigidSwapOptions, CheckRejectsBadValues) {
  RigidSwapOptions options;
  options.max_cluster = 9;
  EXPECT_THROW(options.Check(), std::invalid_argument);
  options = RigidSwapOptions();
  options.improvement = 0.0;
  EXPECT_THROW(options.Check(), std::invalid_argument);
}

}  // namespace
}  // namespace mocap

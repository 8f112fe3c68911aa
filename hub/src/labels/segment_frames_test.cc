// Segment names from the anchors' frame: a near-symmetric cluster on a "shank" is named right on
// another subject (other side lengths) with the limb bent far from its mean pose, where the mean
// shape shifted onto the points names it wrongly; a swap of two wrist markers on a forearm laid
// out along its limb counts as a turn about the limb, a swap inside a cluster around a limb does
// not; anchors are the near, steady neighbours.
#include <algorithm>
#include <cmath>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "labels/segment_frames.h"
#include "util/assignment.h"

namespace mocap {
namespace {

// A leg: thigh cluster (0-2) above, shank cluster (3-5), foot (6-8), plus a far loose marker (9).
// Distances from the mean shape, sd 1 inside a segment, 10 across one joint, 60 otherwise.
MarkerSet Leg() {
  MarkerSet set;
  set.names = {"T.Upper", "T.Front", "T.Rear", "S.Upper", "S.Front", "S.Rear", "F.Heel", "F.Toe", "F.Lat", "Far"};
  set.mean_shape = {{0, 10, 760}, {0, 60, 680}, {0, -50, 690},   // thigh cluster, ~100 mm sides
                    {20, 10, 330}, {0, 55, 260}, {0, -45, 265},  // shank cluster
                    {0, 0, 60}, {0, 260, 30}, {60, 180, 40},      // foot
                    {-400, 0, 1200}};
  set.segments = {{0, 1, 2}, {3, 4, 5}, {6, 7, 8}};
  set.Index();
  for (int a = 0; a < 10; ++a)
    for (int b = a + 1; b < 10; ++b) {
      MarkerDistance d;
      d.a = a, d.b = b;
      d.mean = (set.mean_shape[a] - set.mean_shape[b]).norm();
      const int sa = set.SegmentOf(a), sb = set.SegmentOf(b);
      d.sd = sa == sb && sa >= 0 ? 1.0 : (sa >= 0 && sb >= 0 && std::abs(sa - sb) == 1 ? 10.0 : 60.0);
      d.min = d.mean - 3 * d.sd, d.max = d.mean + 3 * d.sd, d.frames = 100;
      set.distances.push_back(d);
    }
  set.Index();
  return set;
}

TEST(SegmentFrames, AnchorsAreTheNearSteadyNeighbours) {
  const MarkerSet set = Leg();
  const std::vector<SegmentAnchors> anchors = ChooseSegmentAnchors(set);
  ASSERT_EQ(anchors.size(), 3u);
  const SegmentAnchors& shank = anchors[1];
  EXPECT_EQ(shank.segment, 1);
  std::vector<std::vector<int>> got = {shank.anchor[0], shank.anchor[1]};
  std::sort(got.begin(), got.end());
  EXPECT_EQ(got, (std::vector<std::vector<int>>{{0, 1, 2}, {6, 7, 8}}));  // thigh and foot, not the far marker
  EXPECT_FALSE(shank.along_limb);
}

TEST(SegmentFrames, NamesABentClusterOfAnotherSubjectWhereTheShiftedMeanShapeFails) {
  const MarkerSet set = Leg();
  const std::vector<SegmentAnchors> anchors = ChooseSegmentAnchors(set);
  // Another subject: the shank cluster's sides differ (Front moved 15 mm), and the knee bent by
  // 100 degrees about the lateral (x) axis: shank and foot turn about the knee at z = 500.
  std::vector<Eigen::Vector3d> points = set.mean_shape;
  points[4] += Eigen::Vector3d(0, -10, 12);
  const Eigen::Vector3d knee(0, 0, 500);
  const Eigen::Matrix3d bend = Eigen::AngleAxisd(100.0 * M_PI / 180.0, Eigen::Vector3d::UnitX()).toRotationMatrix();
  for (int m = 3; m <= 8; ++m) points[m] = knee + bend * (points[m] - knee);
  const std::vector<int> labels = {0, 1, 2, 3, 4, 5, 6, 7, 8, 9};
  // The mean shape shifted onto the shank's points (no turn): a wrong permutation.
  Eigen::Vector3d now = Eigen::Vector3d::Zero(), mean = Eigen::Vector3d::Zero();
  for (int m = 3; m <= 5; ++m) now += points[m] / 3.0, mean += set.mean_shape[m] / 3.0;
  Eigen::MatrixXd cost(3, 3);
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) cost(i, k) = (set.mean_shape[3 + k] - mean + now - points[3 + i]).squaredNorm();
  const std::vector<int> shifted = SolveAssignment(cost, 1e18);
  EXPECT_FALSE(shifted[0] == 0 && shifted[1] == 1 && shifted[2] == 2);
  std::vector<int> votes;
  VoteInSegmentFrames(set, anchors, points, labels, &votes);
  ASSERT_EQ(votes.size(), points.size());
  for (int m = 0; m <= 8; ++m) EXPECT_EQ(votes[m], m) << set.names[m];
  EXPECT_EQ(votes[9], -1);  // a loose marker gets no vote
  // Without one of its anchors in the frame the shank is not voted on.
  std::vector<int> partial = labels;
  partial[7] = -1;
  VoteInSegmentFrames(set, anchors, points, partial, &votes);
  EXPECT_EQ(votes[3], -1);
  EXPECT_EQ(votes[0], 0);  // the thigh's anchors (the shank and the far marker) are all there
}

TEST(SegmentFrames, ASwapAcrossAForearmIsATurnAboutTheLimbNotOneInsideACluster) {
  MarkerSet set;
  set.names = {"Shoulder", "Bicep", "Elbow", "Wrist.Med", "Wrist.Lat", "Hip"};
  set.mean_shape = {{0, 0, 1400}, {10, 20, 1250}, {0, 0, 1100}, {-30, 0, 850}, {35, 5, 855}, {300, 0, 950}};
  set.segments = {{0, 1}, {2, 3, 4}};
  set.Index();
  for (int a = 0; a < 6; ++a)
    for (int b = a + 1; b < 6; ++b) {
      MarkerDistance d;
      d.a = a, d.b = b, d.mean = (set.mean_shape[a] - set.mean_shape[b]).norm();
      d.sd = set.SegmentOf(a) == set.SegmentOf(b) && set.SegmentOf(a) >= 0 ? 1.0 : (b == 5 ? 20.0 : 5.0);
      d.min = d.mean - 5, d.max = d.mean + 5, d.frames = 100;
      set.distances.push_back(d);
    }
  set.Index();
  const std::vector<SegmentAnchors> anchors = ChooseSegmentAnchors(set);
  ASSERT_EQ(anchors.size(), 1u);
  EXPECT_TRUE(anchors[0].along_limb);
  EXPECT_TRUE(IsTurnAboutLimb(set, anchors[0], {{3, 4}, {4, 3}}));
  const MarkerSet leg = Leg();
  const std::vector<SegmentAnchors> leg_anchors = ChooseSegmentAnchors(leg);
  EXPECT_FALSE(IsTurnAboutLimb(leg, leg_anchors[1], {{4, 5}, {5, 4}}));
  EXPECT_FALSE(IsTurnAboutLimb(leg, leg_anchors[1], {{3, 4}, {4, 5}, {5, 3}}));
}

}  // namespace
}  // namespace mocap

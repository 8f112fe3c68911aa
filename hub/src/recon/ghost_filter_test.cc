// Ghost filter: duplicates of one marker and points made of other markers' blobs are dropped,
// real markers are kept, and dropped points give their blobs back.
#include "recon/ghost_filter.h"

#include <gtest/gtest.h>

#include "recon/triangulation.h"
#include "simcore/test_scenes.h"

namespace mocap {
namespace {

// Three markers seen by an 8-camera ring, without faults.
struct Scene {
  Rig rig = testing::MakeRingRig(8, 4000.0, 2200.0, Eigen::Vector3d(0, 0, 1000));
  RigModel model{rig};
  std::vector<Eigen::Vector3d> markers = {{0, 0, 1000}, {150, 0, 1100}, {-200, 100, 900}};
  FrameSet frame_set;
  testing::BlobTruth truth;
  FrameViews views;
  BlobIndex index;

  Scene() {
    testing::FrameProjector projector(rig, testing::ProjectionFaults(), 5);
    projector.Project(0, markers, &frame_set, &truth);
    BuildFrameViews(model, frame_set, &views);
    index.Build(model, views);
  }

  // The observations of marker m, in camera order.
  std::vector<int> ObservationsOf(int m) const {
    std::vector<int> out;
    for (int o = 0; o < views.NumObservations(); ++o) {
      if (truth[views.observations[o].camera][views.observations[o].blob] == m) out.push_back(o);
    }
    return out;
  }
};

TriangulatedPoint Solve(const RigModel& model, const FrameViews& views, const std::vector<int>& observations) {
  TriangulatedPoint point;
  EXPECT_TRUE(TriangulateRobust(model, views, observations, TriangulationOptions(), &point));
  return point;
}

TEST(GhostFilter, KeepsMarkersDropsDuplicateAndGhost) {
  const Scene scene;
  const RigModel& model = scene.model;
  std::vector<TriangulatedPoint> points;
  for (int m = 0; m < 3; ++m) points.push_back(Solve(model, scene.views, scene.ObservationsOf(m)));
  // A duplicate of marker 0 from three of its views (the full point took the others, say), and
  // a ghost: marker 1's blob in one camera with marker 2's blob in another, the midpoint of
  // their rays.
  const std::vector<int> of0 = scene.ObservationsOf(0);
  ASSERT_GE(of0.size(), 6u);
  points[0].observations.resize(of0.size() - 3);
  points.push_back(Solve(model, scene.views, {of0.end() - 3, of0.end()}));
  const int b = scene.ObservationsOf(1)[0], c = scene.ObservationsOf(2)[1];
  ASSERT_NE(scene.views.observations[b].camera, scene.views.observations[c].camera);
  TriangulatedPoint ghost;
  ghost.observations = {b, c};
  ASSERT_TRUE(TriangulateLinear(model, scene.views, ghost.observations, &ghost.point_in_world));
  points.push_back(ghost);

  UseCounts used(scene.views.NumObservations(), 0);
  for (const TriangulatedPoint& point : points) MarkUsed(point, &used);
  GhostFilter filter{GhostFilterOptions(), TriangulationOptions()};
  std::vector<char> keep;
  EXPECT_EQ(filter.Apply(model, scene.views, scene.index, points, 0, &used, &keep), 2);
  EXPECT_EQ(keep, (std::vector<char>{1, 1, 1, 0, 0}));
  // The duplicate's and the ghost's views are free again where no kept point holds them.
  for (int o : points[3].observations) EXPECT_EQ(used[o], 0);
  EXPECT_EQ(used[b], 1);  // still marker 1's
  EXPECT_EQ(used[c], 1);

  // Every point tracked: the ghost's track vouches for it; the duplicate still goes.
  for (const TriangulatedPoint& point : points) MarkUsed(point, &used);
  EXPECT_EQ(filter.Apply(model, scene.views, scene.index, points, points.size(), &used, &keep), 1);
  EXPECT_EQ(keep, (std::vector<char>{1, 1, 1, 0, 1}));
}

TEST(GhostFilter, DisabledKeepsEverything) {
  const Scene scene;
  const RigModel& model = scene.model;
  std::vector<TriangulatedPoint> points = {Solve(model, scene.views, scene.ObservationsOf(0)),
                                           Solve(model, scene.views, scene.ObservationsOf(0))};
  UseCounts used(scene.views.NumObservations(), 2);
  GhostFilterOptions options;
  options.enabled = false;
  GhostFilter filter{options, TriangulationOptions()};
  std::vector<char> keep;
  EXPECT_EQ(filter.Apply(model, scene.views, scene.index, points, 0, &used, &keep), 0);
  EXPECT_EQ(keep, (std::vector<char>{1, 1}));
}

}  // namespace
}  // namespace mocap

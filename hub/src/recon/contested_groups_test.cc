// Contested groups: grouping, the per-camera assignment of close markers' predictions, and the
// reconstructor leaving the matcher out when every blob is explained.
#include "recon/contested_groups.h"

#include <gtest/gtest.h>

#include "recon/reconstructor.h"
#include "simcore/test_scenes.h"

namespace mocap {
namespace {

PointPrediction Predict(int track, const Eigen::Vector3d& at, double gate_mm) {
  PointPrediction p;
  p.track_id = track;
  p.point_in_world = at;
  p.gate_mm = gate_mm;
  return p;
}

TEST(ContestedGroups, GroupsAreConnectedComponentsOfNearPairs) {
  // 0-1-2 a chain (each pair 40 mm apart, limit 1.5 x (20 + 20) = 60), 3 far, 4 near 3 but not
  // contested (not marked), 5 alone though marked.
  const std::vector<PointPrediction> predictions = {
      Predict(0, {0, 0, 0}, 20), Predict(1, {40, 0, 0}, 20), Predict(2, {80, 0, 0}, 20),
      Predict(3, {500, 0, 0}, 20), Predict(4, {520, 0, 0}, 20), Predict(5, {1000, 0, 0}, 20)};
  const std::vector<char> contested = {1, 1, 1, 1, 0, 1};
  std::vector<int> begin, members;
  FindContestedGroups(predictions, contested, 1.5, 30.0, &begin, &members);
  ASSERT_EQ(begin, (std::vector<int>{0, 3, 4, 5}));
  EXPECT_EQ(members, (std::vector<int>{0, 1, 2, 3, 5}));
  // The cap: two wide gates count as 30 mm each (limit 90): 100 mm apart is no longer a pair.
  const std::vector<PointPrediction> wide = {Predict(0, {0, 0, 0}, 200), Predict(1, {100, 0, 0}, 200)};
  FindContestedGroups(wide, {1, 1}, 1.5, 30.0, &begin, &members);
  EXPECT_EQ(begin, (std::vector<int>{0, 1, 2}));
}

// Two markers 20 mm apart whose predictions are both 12 mm off along the pair: the first
// prediction's nearest blob is, in the cameras that see the pair side by side, its neighbour's.
struct TwoCloseMarkers {
  Rig rig = testing::MakeRingRig(8, 4000.0, 2200.0, Eigen::Vector3d(0, 0, 1000));
  std::vector<Eigen::Vector3d> markers = {{0, 0, 1000}, {20, 0, 1000}};
  FrameSet frame_set;
  testing::BlobTruth truth;
  std::vector<PointPrediction> predictions = {Predict(7, {12, 0, 1000}, 20), Predict(8, {32, 0, 1000}, 20)};
  TwoCloseMarkers() {
    testing::ProjectionFaults faults;
    faults.noise_px = 0.1;
    testing::FrameProjector projector(rig, faults, 5);
    projector.Project(0, markers, &frame_set, &truth);
  }
};

TEST(ContestedGroups, CloseMarkersResolvedToTheirOwnBlobs) {
  TwoCloseMarkers scene;
  const RigModel rig(scene.rig);
  FrameViews views;
  BuildFrameViews(rig, scene.frame_set, &views);
  BlobIndex index;
  index.Build(rig, views);
  PredictionMatchOptions options;
  std::vector<char> contested;
  MarkContested(scene.predictions, options.contested_gate_factor, options.contested_gate_cap_mm, &contested);
  ASSERT_EQ(contested, (std::vector<char>{1, 1}));
  ContestedGroupResolver resolver(options, TriangulationOptions());
  UseCounts used(views.observations.size(), 0);
  std::vector<TriangulatedPoint> points;
  ASSERT_EQ(resolver.Resolve(rig, views, index, scene.predictions, contested, &used, &points), 2);
  EXPECT_EQ(resolver.groups(), 1);
  // Each point is one marker, made of that marker's blobs only, in every camera.
  std::vector<int> found(2, 0);
  for (const TriangulatedPoint& point : points) {
    const int m = (point.point_in_world - scene.markers[0]).norm() < (point.point_in_world - scene.markers[1]).norm()
                      ? 0
                      : 1;
    ++found[static_cast<size_t>(m)];
    EXPECT_LT((point.point_in_world - scene.markers[static_cast<size_t>(m)]).norm(), 1.0);
    EXPECT_EQ(point.observations.size(), 8u);
    for (int o : point.observations) {
      const Observation& obs = views.observations[static_cast<size_t>(o)];
      EXPECT_EQ(scene.truth[static_cast<size_t>(obs.camera)][static_cast<size_t>(obs.blob)], m);
    }
  }
  EXPECT_EQ(found, (std::vector<int>{1, 1}));
  for (unsigned char u : used) EXPECT_EQ(u, 1);
}

TEST(ContestedGroups, NearestBlobsAloneWouldTakeTheNeighbours) {
  // The scene's premise: without the joint assignment, some camera's nearest blob to a
  // prediction is the other marker's, so the test above is not won by the nearest rule.
  TwoCloseMarkers scene;
  const RigModel rig(scene.rig);
  FrameViews views;
  BuildFrameViews(rig, scene.frame_set, &views);
  BlobIndex index;
  index.Build(rig, views);
  int wrong = 0;
  for (int c = 0; c < rig.NumCameras(); ++c) {
    const CameraModel& cam = rig.camera(c);
    const Eigen::Vector3d p =
        cam.cam_from_world_rotation * scene.predictions[0].point_in_world + cam.cam_from_world_translation;
    const int o = index.NearestOfAll(c, p.head<2>() / p.z(), 40.0 / cam.focal_px);
    if (o >= 0 && scene.truth[static_cast<size_t>(c)]
                                         [static_cast<size_t>(views.observations[static_cast<size_t>(o)].blob)] != 0)
      ++wrong;
  }
  EXPECT_GT(wrong, 0);
}

TEST(ContestedGroups, MatcherNotCalledWhenEveryBlobIsExplained) {
  TwoCloseMarkers scene;
  std::vector<ReconstructedPoint> points;
  ReconstructorOptions on;
  on.prediction.resolve_contested_groups = true;
  Reconstructor with(scene.rig, on);
  with.Process(scene.frame_set, scene.predictions, &points);
  ASSERT_EQ(points.size(), 2u);
  for (const ReconstructedPoint& point : points) EXPECT_EQ(point.track_hint, -1);
  EXPECT_EQ(with.stats().points_from_contested_groups, 2);
  EXPECT_EQ(with.stats().matcher_runs, 0);
  EXPECT_EQ(with.stats().leftover_observations, 0);

  // Off (the default): the same two points, found by the matcher from every blob.
  Reconstructor without(scene.rig, ReconstructorOptions());
  without.Process(scene.frame_set, scene.predictions, &points);
  EXPECT_EQ(points.size(), 2u);
  EXPECT_EQ(without.stats().matcher_runs, 1);
  EXPECT_EQ(without.stats().leftover_observations, static_cast<long long>(2 * scene.rig.cameras.size()));
}

}  // namespace
}  // namespace mocap

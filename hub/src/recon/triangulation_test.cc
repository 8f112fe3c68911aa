// Triangulation on noisy synthetic views: accuracy, refinement and outlier-view rejection.
#include "recon/triangulation.h"

#include <random>

#include <gtest/gtest.h>

#include "simcore/test_scenes.h"

namespace mocap {
namespace {

// One frame set with a single blob per camera at the projection of `point` (+ noise).
FrameSet OnePointFrame(const Rig& rig, const Eigen::Vector3d& point, double noise_px,
                       std::mt19937* rng) {
  std::normal_distribution<double> noise(0.0, noise_px);
  FrameSet frame_set;
  for (const Camera& camera : rig.cameras) {
    CameraFrame frame;
    frame.camera_id = camera.id;
    Blob blob;
    EXPECT_TRUE(camera.ProjectToPixel(point, &blob.pixel));
    blob.pixel += Eigen::Vector2d(noise(*rng), noise(*rng));
    frame.blobs.push_back(blob);
    frame_set.cameras.push_back(frame);
  }
  return frame_set;
}

std::vector<int> AllObservations(const FrameViews& views) {
  std::vector<int> all(views.NumObservations());
  for (int i = 0; i < views.NumObservations(); ++i) all[i] = i;
  return all;
}

TEST(Triangulation, ExactViewsGiveExactPointWithDistortion) {
  const Rig rig = testing::MakeRingRig(4, 4000.0, 2000.0, Eigen::Vector3d(0, 0, 1000), 1100.0,
                                       1280, 800, {-0.2, 0.05, 0.001, -0.001, 0.0});
  const RigModel model(rig);
  std::mt19937 rng(1);
  const Eigen::Vector3d truth(123.0, -250.0, 1400.0);
  FrameViews views;
  BuildFrameViews(model, OnePointFrame(rig, truth, 0.0, &rng), &views);
  TriangulatedPoint result;
  ASSERT_TRUE(TriangulateRobust(model, views, AllObservations(views), TriangulationOptions(), &result));
  EXPECT_LT((result.point_in_world - truth).norm(), 1e-6);
  EXPECT_EQ(result.observations.size(), 4u);
  EXPECT_LT(result.max_px, 1e-6);
}

TEST(Triangulation, NoisyViewsStayWithinExpectedError) {
  const Rig rig = testing::MakeRingRig(8, 4000.0, 2000.0, Eigen::Vector3d(0, 0, 1000));
  const RigModel model(rig);
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> coord(-600.0, 600.0);
  double sum_squares = 0.0;
  const int trials = 200;
  for (int trial = 0; trial < trials; ++trial) {
    const Eigen::Vector3d truth(coord(rng), coord(rng), 1000.0 + coord(rng));
    FrameViews views;
    BuildFrameViews(model, OnePointFrame(rig, truth, 0.2, &rng), &views);
    TriangulatedPoint result;
    ASSERT_TRUE(
        TriangulateRobust(model, views, AllObservations(views), TriangulationOptions(), &result));
    sum_squares += (result.point_in_world - truth).squaredNorm();
  }
  // 0.2 px at ~4 m with f = 1100 px is ~0.7 mm per ray; eight views average it down.
  const double rmse = std::sqrt(sum_squares / trials);
  EXPECT_LT(rmse, 0.6);
  EXPECT_GT(rmse, 0.05);  // noise really was applied
}

TEST(Triangulation, RefinementImprovesOnLinearEstimate) {
  const Rig rig = testing::MakeRingRig(3, 4000.0, 2000.0, Eigen::Vector3d(0, 0, 1000));
  const RigModel model(rig);
  std::mt19937 rng(3);
  FrameViews views;
  BuildFrameViews(model, OnePointFrame(rig, Eigen::Vector3d(300, 200, 900), 1.0, &rng), &views);
  Eigen::Vector3d linear;
  ASSERT_TRUE(TriangulateLinear(model, views, AllObservations(views), &linear));
  Eigen::Vector3d refined = linear;
  ASSERT_TRUE(RefinePoint(model, views, AllObservations(views), 10, &refined));
  std::vector<double> before, after;
  ReprojectionErrors(model, views, AllObservations(views), linear, &before);
  ReprojectionErrors(model, views, AllObservations(views), refined, &after);
  double sum_before = 0.0, sum_after = 0.0;
  for (size_t i = 0; i < before.size(); ++i) {
    sum_before += before[i] * before[i];
    sum_after += after[i] * after[i];
  }
  EXPECT_LE(sum_after, sum_before + 1e-12);
}

TEST(Triangulation, RejectsOneOutlierView) {
  const Rig rig = testing::MakeRingRig(5, 4000.0, 2000.0, Eigen::Vector3d(0, 0, 1000));
  const RigModel model(rig);
  std::mt19937 rng(4);
  const Eigen::Vector3d truth(-100.0, 50.0, 1100.0);
  FrameSet frame_set = OnePointFrame(rig, truth, 0.1, &rng);
  frame_set.cameras[2].blobs[0].pixel += Eigen::Vector2d(12.0, -7.0);  // a wrong blob
  FrameViews views;
  BuildFrameViews(model, frame_set, &views);
  TriangulatedPoint result;
  ASSERT_TRUE(TriangulateRobust(model, views, AllObservations(views), TriangulationOptions(), &result));
  ASSERT_EQ(result.rejected.size(), 1u);
  EXPECT_EQ(views.observations[result.rejected[0]].camera, 2);
  EXPECT_EQ(result.observations.size(), 4u);
  EXPECT_LT((result.point_in_world - truth).norm(), 1.0);
}

TEST(Triangulation, TwoInconsistentViewsFail) {
  // Two cameras a quarter turn apart; the second blob moves 30 px, mostly off the epipolar line.
  const Rig rig = testing::MakeRingRig(4, 4000.0, 2000.0, Eigen::Vector3d(0, 0, 1000));
  const RigModel model(rig);
  std::mt19937 rng(5);
  FrameSet frame_set = OnePointFrame(rig, Eigen::Vector3d(0, 0, 1000), 0.0, &rng);
  frame_set.cameras.resize(2);
  frame_set.cameras[1].blobs[0].pixel += Eigen::Vector2d(20.0, 20.0);
  FrameViews views;
  BuildFrameViews(model, frame_set, &views);
  TriangulatedPoint result;
  EXPECT_FALSE(TriangulateRobust(model, views, AllObservations(views), TriangulationOptions(), &result));
}

TEST(Triangulation, UnknownCamerasAreSkippedAndCounted) {
  const Rig rig = testing::MakeRingRig(2, 4000.0, 2000.0, Eigen::Vector3d(0, 0, 1000));
  const RigModel model(rig);
  FrameSet frame_set;
  CameraFrame stranger;
  stranger.camera_id = 99;
  stranger.blobs.resize(3);
  frame_set.cameras.push_back(stranger);
  FrameViews views;
  BuildFrameViews(model, frame_set, &views);
  EXPECT_EQ(views.NumObservations(), 0);
  EXPECT_EQ(views.skipped_unknown_cameras, 1);
}

}  // namespace
}  // namespace mocap

// Ray closest points and the k-partite graph: true correspondences are edges, cliques form.
#include "recon/epipolar_graph.h"

#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "simcore/test_scenes.h"

namespace mocap {
namespace {

TEST(ClosestPointsOfRays, SkewLines) {
  RayPair pair;
  // x axis, and a line parallel to y through (5, 0, 3): closest points (5,0,0) and (5,0,3).
  ASSERT_TRUE(ClosestPointsOfRays(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 0, 0),
                                  Eigen::Vector3d(5, -2, 3), Eigen::Vector3d(0, 1, 0), &pair));
  EXPECT_NEAR(pair.distance, 3.0, 1e-12);
  EXPECT_NEAR((pair.midpoint - Eigen::Vector3d(5, 0, 1.5)).norm(), 0.0, 1e-12);
  EXPECT_NEAR(pair.depth_a, 5.0, 1e-12);
  EXPECT_NEAR(pair.depth_b, 2.0, 1e-12);
  EXPECT_FALSE(ClosestPointsOfRays(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 0, 0),
                                   Eigen::Vector3d(0, 1, 0), Eigen::Vector3d(1, 0, 0), &pair));
}

TEST(EpipolarGraph, TrueCorrespondencesAreEdgesAndFormCliques) {
  const Rig rig = testing::MakeRingRig(6, 4000.0, 2000.0, Eigen::Vector3d(0, 0, 1000));
  const RigModel model(rig);
  testing::SyntheticMotion motion(20, 4, 7);
  testing::ProjectionFaults faults;
  faults.noise_px = 0.2;
  testing::FrameProjector projector(rig, faults, 8);
  FrameSet frame_set;
  testing::BlobTruth truth;
  projector.Project(0, motion.At(0.0), &frame_set, &truth);
  FrameViews views;
  BuildFrameViews(model, frame_set, &views);
  EpipolarGraph graph;
  graph.Build(model, views, EpipolarGraphOptions());
  const auto marker_of = [&](int node) {
    const Observation& obs = views.observations[node];
    return truth[obs.camera][obs.blob];
  };
  int true_pairs = 0;
  for (int a = 0; a < graph.NumNodes(); ++a) {
    for (int b = a + 1; b < graph.NumNodes(); ++b) {
      if (views.observations[a].camera == views.observations[b].camera) continue;
      if (marker_of(a) != marker_of(b)) continue;
      ++true_pairs;
      EXPECT_GE(graph.EdgeDistance(a, b), 0.0f) << "missing true edge " << a << "-" << b;
      EXPECT_EQ(graph.EdgeDistance(a, b), graph.EdgeDistance(b, a));
    }
  }
  EXPECT_GT(true_pairs, 100);
  // The graph is k-partite: no edge inside a camera.
  for (int a = 0; a < graph.NumNodes(); ++a) {
    for (const GraphEdge& edge : graph.Neighbours(a)) {
      EXPECT_NE(views.observations[a].camera, views.observations[edge.other].camera);
    }
  }
  // Every marker seen by all six cameras has its full clique among the candidates.
  const auto cliques = graph.CandidateCliques(model, views);
  for (int marker = 0; marker < motion.NumMarkers(); ++marker) {
    std::vector<int> members;
    for (int node = 0; node < graph.NumNodes(); ++node) {
      if (marker_of(node) == marker) members.push_back(node);
    }
    if (members.size() < 6) continue;
    EXPECT_NE(std::find(cliques.begin(), cliques.end(), members), cliques.end())
        << "marker " << marker;
  }
}

// The graph's cheap bound rules pairs out before the exact closest-points test; it must never
// rule out a pair the exact test keeps. Rays aimed at points scattered around a marker so that
// many pairs pass within a hair of the threshold, on either side of it: the edges are exactly
// the pairs the exact test alone accepts.
TEST(EpipolarGraph, EdgesAreExactlyThePairsTheExactTestKeeps) {
  const Rig rig = testing::MakeRingRig(6, 4000.0, 2000.0, Eigen::Vector3d(0, 0, 1000));
  const RigModel model(rig);
  EpipolarGraphOptions options;
  std::mt19937 random(5);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  long long near_threshold = 0, edges = 0;
  for (int round = 0; round < 40; ++round) {
    const Eigen::Vector3d marker(400.0 * unit(random), 400.0 * unit(random), 1000.0 + 400.0 * unit(random));
    // Offsets up to about the threshold, some rounds much finer, some coarser.
    const double spread = options.max_ray_distance_mm * (round % 3 == 0 ? 0.6 : round % 3 == 1 ? 1.2 : 3.0);
    FrameViews views;
    for (int c = 0; c < model.NumCameras(); ++c) {
      views.camera_begin.push_back(views.NumObservations());
      for (int b = 0; b < 12; ++b) {
        Observation observation;
        observation.camera = c;
        observation.blob = b;
        const Eigen::Vector3d target = marker + spread * Eigen::Vector3d(unit(random), unit(random), unit(random));
        observation.ray_in_world = (target - model.camera(c).center_in_world).normalized();
        views.observations.push_back(observation);
      }
    }
    views.camera_begin.push_back(views.NumObservations());
    EpipolarGraph graph;
    graph.Build(model, views, options);
    for (int i = 0; i < views.NumObservations(); ++i) {
      for (int j = i + 1; j < views.NumObservations(); ++j) {
        const Observation& a = views.observations[i];
        const Observation& b = views.observations[j];
        if (a.camera == b.camera) continue;
        RayPair pair;
        const bool kept = ClosestPointsOfRays(model.camera(a.camera).center_in_world, a.ray_in_world,
                                              model.camera(b.camera).center_in_world, b.ray_in_world, &pair) &&
                          pair.distance <= options.max_ray_distance_mm && pair.depth_a >= options.min_depth_mm &&
                          pair.depth_b >= options.min_depth_mm;
        ASSERT_EQ(graph.EdgeDistance(i, j) >= 0.0f, kept) << "round " << round << " pair " << i << ", " << j
                                                          << " at " << pair.distance << " mm";
        near_threshold += std::abs(pair.distance - options.max_ray_distance_mm) < 0.01 * options.max_ray_distance_mm;
        edges += kept;
      }
    }
  }
  // The draws must put pairs on both sides of the threshold, and close to it.
  EXPECT_GT(edges, 1000);
  EXPECT_GT(near_threshold, 100);
}

}  // namespace
}  // namespace mocap

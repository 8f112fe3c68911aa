// Matcher factory, option checks and the shared acceptance step.
#include "recon/matcher.h"

#include <stdexcept>

#include "recon/clustering_matcher.h"
#include "recon/greedy_matcher.h"
#include "recon/relaxation_matcher.h"

namespace mocap {
namespace {

void Require(bool condition, const char* message) {
  if (!condition) throw std::invalid_argument(message);
}

}  // namespace

void TriangulationOptions::Check() const {
  Require(min_views >= 2, "triangulation.min_views must be >= 2");
  Require(max_reprojection_px > 0.0, "triangulation.max_reprojection_px must be > 0");
  Require(max_merged_px >= max_reprojection_px, "triangulation.max_merged_px must be >= max_reprojection_px");
  Require(refine_iterations >= 0, "triangulation.refine_iterations must be >= 0");
  Require(outlier_floor_px >= 0.0, "triangulation.outlier_floor_px must be >= 0");
  Require(outlier_ratio > 1.0, "triangulation.outlier_ratio must be > 1");
  Require(precise_fraction >= 0.0 && precise_fraction <= 1.0, "triangulation.precise_fraction must lie in 0..1");
  Require(min_depth_mm >= 0.0, "triangulation.min_depth_mm must be >= 0");
}

void EpipolarGraphOptions::Check() const {
  Require(max_ray_distance_mm > 0.0, "graph.max_ray_distance_mm must be > 0");
  Require(min_depth_mm >= 0.0, "graph.min_depth_mm must be >= 0");
}

void RelaxationOptions::Check() const {
  Require(max_iterations >= 1, "relaxation.max_iterations must be >= 1");
  Require(tolerance > 0.0, "relaxation.tolerance must be > 0");
}

void ClusteringOptions::Check() const {
  Require(max_ray_distance_mm > 0.0, "clustering.max_ray_distance_mm must be > 0");
}

void PredictionMatchOptions::Check() const {
  Require(min_gate_px > 0.0, "prediction.min_gate_px must be > 0");
  Require(max_gate_px >= min_gate_px, "prediction.max_gate_px must be >= min_gate_px");
  Require(max_shift_factor > 0.0, "prediction.max_shift_factor must be > 0");
  Require(coincident_px >= 0.0, "prediction.coincident_px must be >= 0");
  Require(contested_gate_factor >= 0.0, "prediction.contested_gate_factor must be >= 0");
  Require(contested_gate_cap_mm > 0.0, "prediction.contested_gate_cap_mm must be > 0");
}

void GhostFilterOptions::Check() const {
  Require(min_separation_mm >= 0.0, "ghosts.min_separation_mm must be >= 0");
}

void ReconstructorOptions::Check() const {
  triangulation.Check();
  graph.Check();
  relaxation.Check();
  clustering.Check();
  prediction.Check();
  ghosts.Check();
  Require(min_views_without_prediction >= triangulation.min_views,
          "min_views_without_prediction must be >= triangulation.min_views");
  Require(seed_cameras == 0 || seed_cameras >= min_views_without_prediction,
          "seed_cameras must be 0 or >= min_views_without_prediction");
  Require(seed_from_blobs_per_camera >= 0.0, "seed_from_blobs_per_camera must be >= 0");
  Require(threads >= 1 && threads <= 256, "threads must be in [1, 256]");
}

std::string MatcherTypeToString(MatcherType type) {
  switch (type) {
    case MatcherType::kRelaxation: return "relaxation";
    case MatcherType::kClustering: return "clustering";
    case MatcherType::kGreedy: return "greedy";
  }
  throw std::invalid_argument("unknown matcher type");
}

MatcherType MatcherTypeFromString(const std::string& name) {
  if (name == "relaxation") return MatcherType::kRelaxation;
  if (name == "clustering") return MatcherType::kClustering;
  if (name == "greedy") return MatcherType::kGreedy;
  throw std::invalid_argument("unknown matcher '" + name +
                              "' (expected relaxation, clustering or greedy)");
}

void MarkUsed(const TriangulatedPoint& point, UseCounts* used) {
  for (int index : point.observations) ++(*used)[index];
}

std::unique_ptr<Matcher> CreateMatcher(const ReconstructorOptions& options) {
  TriangulationOptions triangulation = options.triangulation;
  triangulation.min_views = options.min_views_without_prediction;
  switch (options.matcher) {
    case MatcherType::kRelaxation:
      return std::make_unique<RelaxationMatcher>(options.graph, options.relaxation,
                                                 triangulation);
    case MatcherType::kClustering:
      return std::make_unique<ClusteringMatcher>(options.clustering, options.graph.min_depth_mm,
                                                 triangulation);
    case MatcherType::kGreedy:
      return std::make_unique<GreedyMatcher>(options.graph, triangulation);
  }
  throw std::invalid_argument("unknown matcher type");
}

void AcceptCliquesInOrder(const RigModel& rig, const FrameViews& views,
                          const std::vector<std::vector<int>>& cliques_in_order,
                          const TriangulationOptions& options, UseCounts* used,
                          std::vector<TriangulatedPoint>* points) {
  std::vector<int> available;
  TriangulatedPoint point;
  for (const std::vector<int>& clique : cliques_in_order) {
    available.clear();
    for (int index : clique) {
      if (IsAvailable(views.observations[index], (*used)[index])) available.push_back(index);
    }
    if (static_cast<int>(available.size()) < options.min_views) continue;
    if (!TriangulateRobust(rig, views, available, options, &point)) continue;
    MarkUsed(point, used);
    points->push_back(point);
  }
}

}  // namespace mocap

// Matcher factory, option checks and the shared acceptance step.
#include "recon/matcher.h"

#include <algorithm>
#include <cstdio>
#include <stdexcept>

#include "recon/clustering_matcher.h"
#include "recon/greedy_matcher.h"
#include "recon/relaxation_matcher.h"

namespace mocap {
namespace {

void Require(bool condition, const std::string& message) {
  if (!condition) throw std::invalid_argument(message);
}

constexpr int kMaxViews = 64;
constexpr double kMaxNoisePx = 50.0;

std::string FormatNumber(double value) {
  char text[32];
  std::snprintf(text, sizeof(text), "%g", value);
  return text;
}

}  // namespace

void TriangulationOptions::Check() const {
  Require(min_views >= 2, "triangulation.min_views must be >= 2");
  Require(max_reprojection_px > 0.0, "triangulation.max_reprojection_px must be > 0");
  Require(max_merged_px >= 0.0, "triangulation.max_merged_px must be >= 0");
  Require(refine_iterations >= 0, "triangulation.refine_iterations must be >= 0");
  Require(outlier_floor_px >= 0.0, "triangulation.outlier_floor_px must be >= 0");
  Require(outlier_ratio > 1.0, "triangulation.outlier_ratio must be > 1");
  Require(precise_fraction >= 0.0 && precise_fraction <= 1.0, "triangulation.precise_fraction must lie in 0..1");
  Require(min_depth_mm >= 0.0, "triangulation.min_depth_mm must be >= 0");
  Require(two_view_max_unseen >= 0, "triangulation.two_view_max_unseen must be >= 0");
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
  Require(min_views_without_prediction >= triangulation.min_views && min_views_without_prediction <= kMaxViews,
          "min_views_without_prediction " + std::to_string(min_views_without_prediction) + " is out of range " +
              std::to_string(triangulation.min_views) + ".." + std::to_string(kMaxViews));
  Require(centroid_noise_px >= 0.0 && centroid_noise_px <= kMaxNoisePx,
          "centroid_noise_px " + FormatNumber(centroid_noise_px) + " is out of range 0..50 (0: measured)");
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

namespace {

// Whether more than `limit` cameras other than the point's own have it in their image, in
// front: cameras that should have seen it. A marker in the middle of an 8-camera ring seen by two
// of them only is far less likely than two rays of other markers' blobs crossing there. Stops at
// the first camera over the limit (spurious pairs on a large rig: after a few cameras).
bool OthersShouldSee(const RigModel& rig, const FrameViews& views, const std::vector<int>& observations,
                  const Eigen::Vector3d& point, double min_depth_mm, int limit) {
  int count = 0;
  for (int c = 0; c < rig.NumCameras() && count <= limit; ++c) {
    bool own = false;
    for (int index : observations) own = own || views.observations[index].camera == c;
    if (own) continue;
    const Camera& camera = *rig.camera(c).camera;
    Eigen::Vector2d pixel;
    if (camera.PointInCamera(point).z() < min_depth_mm || !camera.ProjectToPixel(point, &pixel)) continue;
    count += camera.InImage(pixel);
  }
  return count > limit;
}

void AcceptPass(const RigModel& rig, const FrameViews& views, const std::vector<std::vector<int>>& cliques_in_order,
                const TriangulationOptions& options, int min_views, UseCounts* used,
                std::vector<TriangulatedPoint>* points) {
  TriangulationOptions pass_options = options;
  pass_options.min_views = min_views;
  std::vector<int> available;
  TriangulatedPoint point;
  for (const std::vector<int>& clique : cliques_in_order) {
    available.clear();
    for (int index : clique) {
      if (IsAvailable(views.observations[index], (*used)[index])) available.push_back(index);
    }
    if (static_cast<int>(available.size()) < min_views) continue;
    if (static_cast<int>(available.size()) == 2) {
      Eigen::Vector3d linear;
      if (!TriangulateLinear(rig, views, available, &linear) ||
          OthersShouldSee(rig, views, available, linear, options.min_depth_mm, options.two_view_max_unseen)) {
        continue;
      }
    }
    if (!TriangulateRobust(rig, views, available, pass_options, &point)) continue;
    MarkUsed(point, used);
    points->push_back(point);
  }
}

}  // namespace

void AcceptCliquesInOrder(const RigModel& rig, const FrameViews& views,
                          const std::vector<std::vector<int>>& cliques_in_order,
                          const TriangulationOptions& options, UseCounts* used,
                          std::vector<TriangulatedPoint>* points) {
  // Points of three or more views first, whatever their order: a two-view candidate must not
  // take a blob a better-supported point needs.
  AcceptPass(rig, views, cliques_in_order, options, std::max(3, options.min_views), used, points);
  if (options.min_views == 2) AcceptPass(rig, views, cliques_in_order, options, 2, used, points);
}

}  // namespace mocap

// Graph construction (all camera pairs, all active observation pairs) and clique growth.
#include "recon/epipolar_graph.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Geometry>

namespace mocap {

bool ClosestPointsOfRays(const Eigen::Vector3d& center_a, const Eigen::Vector3d& direction_a,
                         const Eigen::Vector3d& center_b, const Eigen::Vector3d& direction_b,
                         RayPair* pair) {
  // Seed 000 (4.3): the segment between the closest points is perpendicular to both rays.
  const Eigen::Vector3d w0 = center_a - center_b;
  const double b = direction_a.dot(direction_b);
  const double d = direction_a.dot(w0);
  const double e = direction_b.dot(w0);
  const double denominator = 1.0 - b * b;  // unit directions: a = c = 1
  if (denominator < 1e-12) return false;
  const double s = (b * e - d) / denominator;
  const double t = (e - b * d) / denominator;
  const Eigen::Vector3d on_a = center_a + s * direction_a;
  const Eigen::Vector3d on_b = center_b + t * direction_b;
  pair->distance = (on_a - on_b).norm();
  pair->midpoint = 0.5 * (on_a + on_b);
  pair->depth_a = s;
  pair->depth_b = t;
  return true;
}

namespace {

// True when the lines of two rays certainly pass farther apart than max_distance_mm: their
// distance |w . n| / |n| (w = centre_a - centre_b, n = a x b) against the limit with a 0.1 %
// margin, without the divisions and the square root of ClosestPointsOfRays. Most pairs of leftover
// blobs (spurious ones, markers no prediction took) are this far apart. The caller gives
// w_cross_a = w x a, computed once per ray of camera a, so that w . n = (w x a) . b, and for unit
// rays |n|^2 = 1 - (a . b)^2. Nearly parallel rays (|n| under 1e-4, where rounding in n grows) are
// never ruled out here; elsewhere rounding moves either distance by far less than the margin, so
// every pair ruled out would fail the exact test too.
bool RaysCertainlyApart(const Eigen::Vector3d& direction_a, const Eigen::Vector3d& w_cross_a,
                        const Eigen::Vector3d& direction_b, double max_distance_mm) {
  const double cosine = direction_a.dot(direction_b);
  const double n2 = 1.0 - cosine * cosine;
  if (!(n2 > 1e-8)) return false;
  const double along_n = w_cross_a.dot(direction_b);
  const double limit = 1.001 * max_distance_mm;
  return along_n * along_n > limit * limit * n2;
}

}  // namespace

void EpipolarGraph::Build(const RigModel& rig, const FrameViews& views,
                          const EpipolarGraphOptions& options, const std::vector<char>& active) {
  const int n = views.NumObservations();
  // Clear rather than reassign: the inner vectors keep their capacity from frame to frame.
  for (int i : active_nodes_) {
    if (i < static_cast<int>(adjacency_.size())) adjacency_[i].clear();
  }
  adjacency_.resize(n);
  active_nodes_.clear();
  num_edges_ = 0;
  const int num_cameras = rig.NumCameras();
  // Active observations per camera first: after the prediction pass only a few blobs per
  // camera are left, and the pair loops must not walk all the others.
  // Their rays beside them, one after another: the pair loops read every ray of the second camera
  // once per blob of the first.
  active_of_camera_.resize(num_cameras);
  active_rays_.resize(num_cameras);
  for (int c = 0; c < num_cameras; ++c) {
    active_of_camera_[c].clear();
    active_rays_[c].clear();
    for (int i = views.camera_begin[c]; i < views.camera_begin[c + 1]; ++i) {
      if (active.empty() || active[i] != 0) {
        active_of_camera_[c].push_back(i);
        active_rays_[c].push_back(views.observations[i].ray_in_world);
        active_nodes_.push_back(i);
      }
    }
  }
  const std::vector<std::vector<int>>& active_of_camera = active_of_camera_;
  RayPair pair;
  for (int ca = 0; ca < num_cameras; ++ca) {
    if (active_of_camera[ca].empty()) continue;
    const Eigen::Vector3d& center_a = rig.camera(ca).center_in_world;
    for (int cb = ca + 1; cb < num_cameras; ++cb) {
      const Eigen::Vector3d& center_b = rig.camera(cb).center_in_world;
      const Eigen::Vector3d baseline = center_a - center_b;
      const std::vector<Eigen::Vector3d>& rays_b = active_rays_[cb];
      for (int i : active_of_camera[ca]) {
        const Eigen::Vector3d& ray_a = views.observations[i].ray_in_world;
        const Eigen::Vector3d baseline_cross_a = baseline.cross(ray_a);
        for (size_t jb = 0; jb < rays_b.size(); ++jb) {
          const Eigen::Vector3d& ray_b = rays_b[jb];
          if (RaysCertainlyApart(ray_a, baseline_cross_a, ray_b, options.max_ray_distance_mm)) continue;
          const int j = active_of_camera[cb][jb];
          if (!ClosestPointsOfRays(center_a, ray_a, center_b, ray_b, &pair)) {
            continue;
          }
          if (pair.distance > options.max_ray_distance_mm || pair.depth_a < options.min_depth_mm ||
              pair.depth_b < options.min_depth_mm) {
            continue;
          }
          const float distance = static_cast<float>(pair.distance);
          adjacency_[i].push_back({j, distance});
          adjacency_[j].push_back({i, distance});
          ++num_edges_;
        }
      }
    }
  }
  // Camera-major loops already add neighbours of i in increasing index for cameras after i's,
  // but neighbours from earlier cameras arrive interleaved: sort once for binary search.
  for (int i : active_nodes_) {
    std::vector<GraphEdge>& neighbours = adjacency_[i];
    std::sort(neighbours.begin(), neighbours.end(),
              [](const GraphEdge& x, const GraphEdge& y) { return x.other < y.other; });
  }
}

float EpipolarGraph::EdgeDistance(int a, int b) const {
  const std::vector<GraphEdge>& neighbours = adjacency_[a];
  const auto it = std::lower_bound(neighbours.begin(), neighbours.end(), b,
                                   [](const GraphEdge& edge, int node) { return edge.other < node; });
  if (it == neighbours.end() || it->other != b) return -1.0f;
  return it->distance_mm;
}

std::vector<std::vector<int>> EpipolarGraph::CandidateCliques(const RigModel& rig,
                                                              const FrameViews& views) const {
  std::vector<std::vector<int>> cliques;
  const int n = NumNodes();
  const int num_cameras = rig.NumCameras();
  std::vector<int> best_in_camera(num_cameras);
  std::vector<double> best_distance(num_cameras);
  // neighbour_of_b[k] == b marks k adjacent to the current b: an O(1) test instead of a search.
  // Only active nodes have edges, so only their marks are read, and reset here.
  std::vector<int>& neighbour_of_b = neighbour_of_b_;
  if (neighbour_of_b.size() < static_cast<size_t>(n)) neighbour_of_b.resize(n);
  for (int node : active_nodes_) neighbour_of_b[node] = -1;
  std::vector<std::pair<double, int>> order;
  // Cliques each node already belongs to: an edge whose ends share one grows the same clique
  // again (a marker seen by k cameras has k(k-1)/2 edges), so it is skipped. Only active nodes
  // have edges: they get a slot each.
  std::vector<int>& slot_of = slot_of_;
  if (slot_of.size() < static_cast<size_t>(n)) slot_of.resize(n);
  for (size_t k = 0; k < active_nodes_.size(); ++k) slot_of[active_nodes_[k]] = static_cast<int>(k);
  std::vector<std::vector<int>>& clique_lists = clique_lists_;
  if (clique_lists.size() < active_nodes_.size()) clique_lists.resize(active_nodes_.size());
  for (size_t k = 0; k < active_nodes_.size(); ++k) clique_lists[k].clear();
  const auto cliques_of = [&](int node) -> std::vector<int>& { return clique_lists[slot_of[node]]; };
  RayPair pair;
  // active_nodes_ is in increasing index order (cameras in order, their observations in order).
  for (int a : active_nodes_) {
    for (const GraphEdge& edge : adjacency_[a]) {
      const int b = edge.other;
      if (b < a) continue;
      bool covered = false;
      const std::vector<int>& of_b = cliques_of(b);
      for (int k : cliques_of(a)) {
        if (std::find(of_b.begin(), of_b.end(), k) != of_b.end()) {
          covered = true;
          break;
        }
      }
      if (covered) continue;
      for (const GraphEdge& e : adjacency_[b]) neighbour_of_b[e.other] = b;
      const Observation& oa = views.observations[a];
      const Observation& ob = views.observations[b];
      if (!ClosestPointsOfRays(rig.camera(oa.camera).center_in_world, oa.ray_in_world,
                               rig.camera(ob.camera).center_in_world, ob.ray_in_world, &pair)) {
        continue;
      }
      // Common neighbours of a and b, the closest to the pair's 3D point per camera.
      std::fill(best_in_camera.begin(), best_in_camera.end(), -1);
      for (const GraphEdge& candidate : adjacency_[a]) {
        const int k = candidate.other;
        const Observation& ok = views.observations[k];
        if (ok.camera == ob.camera || neighbour_of_b[k] != b) continue;
        const Eigen::Vector3d to_point = pair.midpoint - rig.camera(ok.camera).center_in_world;
        const double off_ray = (to_point - to_point.dot(ok.ray_in_world) * ok.ray_in_world).norm();
        if (best_in_camera[ok.camera] < 0 || off_ray < best_distance[ok.camera]) {
          best_in_camera[ok.camera] = k;
          best_distance[ok.camera] = off_ray;
        }
      }
      // Add the common neighbours nearest first, each only if adjacent to all members so far.
      order.clear();
      for (int c = 0; c < num_cameras; ++c) {
        if (best_in_camera[c] >= 0) order.emplace_back(best_distance[c], best_in_camera[c]);
      }
      std::sort(order.begin(), order.end());
      std::vector<int> clique = {a, b};
      for (const auto& [distance, k] : order) {
        bool adjacent_to_all = true;
        for (size_t m = 2; m < clique.size() && adjacent_to_all; ++m) {
          adjacent_to_all = EdgeDistance(clique[m], k) >= 0.0f;
        }
        if (adjacent_to_all) clique.push_back(k);
      }
      std::sort(clique.begin(), clique.end());
      for (int member : clique) cliques_of(member).push_back(static_cast<int>(cliques.size()));
      cliques.push_back(std::move(clique));
    }
  }
  // Every edge of a k-view marker grows the same clique: keep one of each.
  std::sort(cliques.begin(), cliques.end());
  cliques.erase(std::unique(cliques.begin(), cliques.end()), cliques.end());
  return cliques;
}

}  // namespace mocap

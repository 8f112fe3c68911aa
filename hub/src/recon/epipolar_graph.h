// The k-partite epipolar graph of one frame (seed 001 section 2.1): nodes are observations, one
// part per camera, and an edge joins two observations of different cameras whose rays pass
// closer than a threshold (mm), in front of both cameras. Candidate cliques (the labels of the
// relaxation) grow from each edge by adding, camera by camera, the observation adjacent to every
// member whose ray passes closest to the edge's 3D point.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "recon/frame_views.h"
#include "recon/recon_options.h"

namespace mocap {

struct RayPair {
  double distance = 0.0;  // closest distance between the two rays, mm
  Eigen::Vector3d midpoint = Eigen::Vector3d::Zero();
  double depth_a = 0.0;  // along ray a from its camera centre
  double depth_b = 0.0;
};

// Closest points of two rays given by centres and unit directions; false when parallel.
bool ClosestPointsOfRays(const Eigen::Vector3d& center_a, const Eigen::Vector3d& direction_a,
                         const Eigen::Vector3d& center_b, const Eigen::Vector3d& direction_b,
                         RayPair* pair);

struct GraphEdge {
  int other = 0;
  float distance_mm = 0.0f;
};

class EpipolarGraph {
 public:
  // Builds edges among observations whose `active` flag is set (all when empty).
  void Build(const RigModel& rig, const FrameViews& views, const EpipolarGraphOptions& options,
             const std::vector<char>& active = {});

  int NumNodes() const { return static_cast<int>(adjacency_.size()); }
  int NumEdges() const { return num_edges_; }
  // Neighbours sorted by node index.
  const std::vector<GraphEdge>& Neighbours(int node) const { return adjacency_[node]; }
  // Ray distance of edge (a, b), or a negative value when they are not adjacent.
  float EdgeDistance(int a, int b) const;

  // Distinct candidate cliques (sorted member lists, at most one member per camera, at least
  // two members), in a deterministic order.
  std::vector<std::vector<int>> CandidateCliques(const RigModel& rig, const FrameViews& views) const;

 private:
  std::vector<std::vector<GraphEdge>> adjacency_;
  // Nodes given an edge list this frame: after the prediction pass a frame of thousands of
  // blobs leaves a few dozen active, and per-frame work must follow those, not all nodes.
  std::vector<int> active_nodes_;
  std::vector<std::vector<int>> active_of_camera_;
  std::vector<std::vector<Eigen::Vector3d>> active_rays_;  // their rays, in the same order
  // CandidateCliques' scratch, kept from frame to frame: only the active nodes' entries are read,
  // and they are set (or reset) at the start of each call. So CandidateCliques, though const, must
  // not run on two threads at once on one graph (each matcher owns its graph).
  mutable std::vector<int> neighbour_of_b_, slot_of_;
  mutable std::vector<std::vector<int>> clique_lists_;
  int num_edges_ = 0;
};

}  // namespace mocap

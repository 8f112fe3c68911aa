// Identity repair inside rigid marker clusters. Markers a few centimetres apart on one rigid
// plate or segment (technical clusters, hands, faces) can turn faster than any constant-velocity
// prediction follows, and then each prediction lands nearer a neighbour than its own marker.
// What does not change is the cluster's shape: the tracks linked by steady distances (the rigid
// model's links) are grouped into small clusters, and when another permutation of the points the
// cluster's tracks hold fits their steady distances far better than the one the predictions chose,
// the points are permuted. When no order of its own points fits (clusters that traded markers: a
// neighbour's track holds one), a cluster of three or more is gathered again from the points
// around it by its steady distances, and the tracks that held those points lose them.
// Single-threaded; per-frame cost grows with the tracks holding points times those in clusters
// (a regathering searches at most 24 nearby points, pruned by distance, in at most 20000 steps);
// never throws on data.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "recon/reconstructor.h"
#include "track/rigid_model.h"
#include "track/track_options.h"

namespace mocap {

class RigidSwapResolver {
 public:
  explicit RigidSwapResolver(const RigidSwapOptions& options) : options_(options) {}

  // eligible[slot]: the track may take part (confirmed). point_of_slot[slot]: the point it holds
  // or -1. Permutes points within clusters and sets (*changed)[slot] for tracks whose point
  // changed; returns how many clusters were repaired.
  int Resolve(const RigidModel& rigid, const std::vector<char>& eligible,
              const std::vector<ReconstructedPoint>& points, std::vector<int>* point_of_slot,
              std::vector<char>* changed);

 private:
  struct Constraint {
    int member;      // index into the cluster of the constrained track
    int other_slot;  // the linked track's slot
    double mean_mm;
  };

  static constexpr size_t kMaxRegatherCandidates = 24;
  static constexpr int kMaxRegatherSteps = 20000;

  bool Steady(const RigidLink* link) const;
  // The cluster's points gathered again from every point within cluster_radius_mm of the ones its
  // members hold, by its own steady distances: clusters that traded markers (a neighbour's track
  // holds one). Tracks outside the cluster that held the points chosen lose them for the frame.
  void Regather(const RigidModel& rigid, const std::vector<int>& cluster,
                const std::vector<ReconstructedPoint>& points, std::vector<int>* point_of_slot,
                std::vector<char>* changed, int* repaired);
  void RepairCluster(const RigidModel& rigid, const std::vector<int>& cluster,
                     const std::vector<ReconstructedPoint>& points, std::vector<int>* point_of_slot,
                     std::vector<char>* changed, int* repaired);

  RigidSwapOptions options_;
  std::vector<int> measured_;
  std::vector<int> parent_;
  // Resolve's clusters: each measured track's root, the members grouped by root (cluster
  // root's members at [cluster_begin_[root], cluster_begin_[root + 1])), one cluster at a time.
  std::vector<int> root_of_, cluster_begin_, cluster_members_, cluster_;
  std::vector<char> in_cluster_;
  std::vector<Constraint> constraints_;
  std::vector<int> candidates_;
};

}  // namespace mocap

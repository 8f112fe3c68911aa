// Rigid-cluster permutation repair.
#include "track/rigid_swaps.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>

#include "util/union_find.h"

namespace mocap {

bool RigidSwapResolver::Steady(const RigidLink* link) const {
  return link != nullptr && !link->broken && link->samples >= options_.min_samples &&
         link->Variance() <= options_.link_std_mm * options_.link_std_mm;
}

int RigidSwapResolver::Resolve(const RigidModel& rigid, const std::vector<char>& eligible,
                               const std::vector<ReconstructedPoint>& points, std::vector<int>* point_of_slot,
                               std::vector<char>* changed) {
  if (!options_.enabled) return 0;
  measured_.clear();
  for (size_t slot = 0; slot < point_of_slot->size(); ++slot) {
    if (eligible[slot] && (*point_of_slot)[slot] >= 0) measured_.push_back(static_cast<int>(slot));
  }
  const int n = static_cast<int>(measured_.size());
  parent_.resize(n);
  std::iota(parent_.begin(), parent_.end(), 0);
  bool any = false;
  for (int i = 0; i < n; ++i) {
    for (int j = i + 1; j < n; ++j) {
      const RigidLink* link = rigid.Link(measured_[i], measured_[j]);
      if (!Steady(link) || link->mean > options_.cluster_radius_mm) continue;
      parent_[FindRoot(parent_, j)] = FindRoot(parent_, i);
      any = true;
    }
  }
  if (!any) return 0;
  std::map<int, std::vector<int>> clusters;  // root -> slots
  for (int i = 0; i < n; ++i) clusters[FindRoot(parent_, i)].push_back(measured_[i]);
  int repaired = 0;
  for (const auto& [root, cluster] : clusters) {
    if (cluster.size() < 2 || static_cast<int>(cluster.size()) > options_.max_cluster) continue;
    RepairCluster(rigid, cluster, points, point_of_slot, changed, &repaired);
  }
  return repaired;
}

void RigidSwapResolver::RepairCluster(const RigidModel& rigid, const std::vector<int>& cluster,
                                      const std::vector<ReconstructedPoint>& points,
                                      std::vector<int>* point_of_slot, std::vector<char>* changed, int* repaired) {
  const int size = static_cast<int>(cluster.size());
  // Every steady link of a member, to another member or to any track holding a point.
  constraints_.clear();
  for (int m = 0; m < size; ++m) {
    for (int other : measured_) {
      if (other == cluster[m]) continue;
      const RigidLink* link = rigid.Link(cluster[m], other);
      if (Steady(link)) constraints_.push_back({m, other, link->mean});
    }
  }
  if (constraints_.empty()) return;
  int member_of[8];
  std::vector<int> held(size);
  for (int m = 0; m < size; ++m) held[m] = (*point_of_slot)[cluster[m]];
  auto cost_of = [&](const int* permutation) {
    double sum = 0.0;
    for (const Constraint& c : constraints_) {
      const Eigen::Vector3d& at = points[held[permutation[c.member]]].point_in_world;
      const auto inside = std::find(cluster.begin(), cluster.end(), c.other_slot);
      const int other_point = inside != cluster.end() ? held[permutation[inside - cluster.begin()]]
                                                      : (*point_of_slot)[c.other_slot];
      const double error = (at - points[other_point].point_in_world).norm() - c.mean_mm;
      sum += error * error;
    }
    return sum;
  };
  int permutation[8];
  std::iota(permutation, permutation + size, 0);
  const double current = cost_of(permutation);
  const double links = static_cast<double>(constraints_.size());
  if (std::sqrt(current / links) <= options_.min_error_mm) return;
  double best = current;
  std::copy(permutation, permutation + size, member_of);
  while (std::next_permutation(permutation, permutation + size)) {
    const double cost = cost_of(permutation);
    if (cost < best) {
      best = cost;
      std::copy(permutation, permutation + size, member_of);
    }
  }
  if (!(best < options_.improvement * current)) return;
  for (int m = 0; m < size; ++m) {
    if (member_of[m] == m) continue;
    (*point_of_slot)[cluster[m]] = held[member_of[m]];
    (*changed)[cluster[m]] = 1;
  }
  ++*repaired;
}

}  // namespace mocap

// Rigid-cluster permutation repair.
#include "track/rigid_swaps.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <numeric>

#include "util/counting_sort.h"
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
      // A link that does not hold is never steady: its byte rules out most pairs unread.
      if (!rigid.Holds(measured_[i], measured_[j])) continue;
      const RigidLink* link = rigid.Link(measured_[i], measured_[j]);
      // The distance first: it is cheaper than Steady's variance and rules out most pairs.
      if (link->mean > options_.cluster_radius_mm || !Steady(link)) continue;
      parent_[FindRoot(parent_, j)] = FindRoot(parent_, i);
      any = true;
    }
  }
  if (!any) return 0;
  // The clusters by root, in the order of their roots, each member's slot in measured order: a
  // counting sort on the root (kept buffers instead of a map of vectors allocated every frame).
  root_of_.resize(n);
  for (int i = 0; i < n; ++i) root_of_[i] = FindRoot(parent_, i);
  cluster_members_.resize(n);
  CountingSort(
      n, n, [&](int i) { return root_of_[i]; }, &cluster_begin_,
      [&](int i, int slot) { cluster_members_[slot] = measured_[i]; });
  int repaired = 0;
  for (int root = 0; root < n; ++root) {
    const int size = cluster_begin_[root + 1] - cluster_begin_[root];
    if (size < 2 || size > options_.max_cluster) continue;
    cluster_.assign(cluster_members_.begin() + cluster_begin_[root], cluster_members_.begin() + cluster_begin_[root + 1]);
    RepairCluster(rigid, cluster_, points, point_of_slot, changed, &repaired);
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
      // A steady link holds: the state byte passes over the others without reading their links.
      if (!rigid.Holds(cluster[m], other)) continue;
      const RigidLink* link = rigid.Link(cluster[m], other);
      if (Steady(link)) constraints_.push_back({m, other, link->mean});
    }
  }
  if (constraints_.empty()) return;
  int member_of[8];
  std::vector<int> held(size);
  for (int m = 0; m < size; ++m) held[m] = (*point_of_slot)[cluster[m]];
  // A member lost its point to an earlier cluster's regathering this frame: gather this one again.
  if (std::find(held.begin(), held.end(), -1) != held.end()) {
    Regather(rigid, cluster, points, point_of_slot, changed, repaired);
    return;
  }
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
  if (!(best < options_.improvement * current)) {
    // No order of its own points fits: a neighbouring cluster's track holds one of them.
    if (std::sqrt(best / links) > options_.min_error_mm) Regather(rigid, cluster, points, point_of_slot, changed, repaired);
    return;
  }
  for (int m = 0; m < size; ++m) {
    if (member_of[m] == m) continue;
    (*point_of_slot)[cluster[m]] = held[member_of[m]];
    (*changed)[cluster[m]] = 1;
  }
  ++*repaired;
}

void RigidSwapResolver::Regather(const RigidModel& rigid, const std::vector<int>& cluster,
                                 const std::vector<ReconstructedPoint>& points, std::vector<int>* point_of_slot,
                                 std::vector<char>* changed, int* repaired) {
  const int size = static_cast<int>(cluster.size());
  if (size < 3 || !options_.regather) return;  // two markers: one distance cannot say which is which
  // The cluster's own shape: every pair of members steadily linked (a rigid plate).
  double mean[8][8];
  for (int a = 0; a < size; ++a) {
    for (int b = a + 1; b < size; ++b) {
      const RigidLink* link = rigid.Link(cluster[a], cluster[b]);
      if (!Steady(link)) return;
      mean[a][b] = mean[b][a] = link->mean;
    }
  }
  // Around the points the members still hold.
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  int held = 0;
  for (int slot : cluster) {
    if ((*point_of_slot)[slot] < 0) continue;
    centre += points[(*point_of_slot)[slot]].point_in_world;
    ++held;
  }
  if (held == 0) return;
  centre /= held;
  candidates_.clear();
  for (int i = 0; i < static_cast<int>(points.size()); ++i) {
    if ((points[i].point_in_world - centre).norm() <= options_.cluster_radius_mm) candidates_.push_back(i);
  }
  if (static_cast<int>(candidates_.size()) < size || candidates_.size() > kMaxRegatherCandidates) return;
  // Depth-first over members, each taking a candidate whose distances to the members placed so
  // far are all within the tolerance; the smallest sum of squared misses wins. The search visits
  // at most kMaxRegatherSteps placements (points crowded at the cluster's own distances could
  // otherwise make it combinatorial); it then keeps the best found so far.
  const double tolerance = 2.0 * options_.min_error_mm;
  int chosen[8], best_choice[8];
  double best_cost = HUGE_VAL;
  int steps = 0;
  const std::function<void(int, double)> place = [&](int member, double cost) {
    if (++steps > kMaxRegatherSteps) return;
    if (member == size) {
      if (cost < best_cost) {
        best_cost = cost;
        std::copy(chosen, chosen + size, best_choice);
      }
      return;
    }
    for (int candidate : candidates_) {
      if (std::find(chosen, chosen + member, candidate) != chosen + member) continue;
      double added = 0.0;
      bool fits = true;
      for (int other = 0; other < member && fits; ++other) {
        const double miss =
            (points[candidate].point_in_world - points[chosen[other]].point_in_world).norm() - mean[member][other];
        fits = std::abs(miss) <= tolerance;
        added += miss * miss;
      }
      if (!fits || cost + added >= best_cost) continue;
      chosen[member] = candidate;
      place(member + 1, cost + added);
    }
  };
  place(0, 0.0);
  const double pairs = 0.5 * size * (size - 1);
  if (!(best_cost < HUGE_VAL) || std::sqrt(best_cost / pairs) > options_.min_error_mm) return;
  for (int m = 0; m < size; ++m) {
    const int point = best_choice[m];
    if ((*point_of_slot)[cluster[m]] == point) continue;
    // A track outside the cluster holding the point loses it for this frame.
    for (size_t slot = 0; slot < point_of_slot->size(); ++slot) {
      if ((*point_of_slot)[slot] != point || std::find(cluster.begin(), cluster.end(), static_cast<int>(slot)) != cluster.end()) continue;
      (*point_of_slot)[slot] = -1;
      (*changed)[slot] = 0;
    }
    (*point_of_slot)[cluster[m]] = point;
    (*changed)[cluster[m]] = 1;
  }
  ++*repaired;
}

}  // namespace mocap

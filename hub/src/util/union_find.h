// Disjoint sets over indices 0..n-1 as a parent array (parent[i] == i for a root): the grouping
// step shared by the simulator's blob merging and the tracker's rigid clusters.
#pragma once

#include <vector>

namespace mocap {

// The root of i's set, halving the path on the way.
inline int FindRoot(std::vector<int>& parent, int i) {
  while (parent[i] != i) {
    parent[i] = parent[parent[i]];
    i = parent[i];
  }
  return i;
}

}  // namespace mocap

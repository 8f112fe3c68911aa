// How smoothly a trajectory's past continues into a future: the squared second differences at
// the two frames around the join, for positions one frame apart (mm^2 per frame^4). Used where
// identities are judged by smoothness (track/hindsight_swaps, eval's truth exchanges).
#pragma once

#include <Eigen/Core>

namespace mocap {

// past_2, past_1: the last two positions before the join (oldest first); next_0, next_1: the
// first two after it.
inline double JoinRoughness(const Eigen::Vector3d& past_2, const Eigen::Vector3d& past_1,
                            const Eigen::Vector3d& next_0, const Eigen::Vector3d& next_1) {
  return (next_0 - 2.0 * past_1 + past_2).squaredNorm() + (next_1 - 2.0 * next_0 + past_1).squaredNorm();
}

}  // namespace mocap

// How smoothly a trajectory's past continues into a future: the squared second differences at
// the two frames around the join, for positions one frame apart (mm^2 per frame^4). Used where
// identities are judged by smoothness (track/hindsight_swaps, eval's truth exchanges).
#pragma once

#include <Eigen/Core>

namespace mocap {

// The squared second difference at `here` of three positions one frame apart.
inline double SquaredSecondDifference(const Eigen::Vector3d& before, const Eigen::Vector3d& here,
                                      const Eigen::Vector3d& after) {
  return (after - 2.0 * here + before).squaredNorm();
}

// past_2, past_1: the last two positions before the join (oldest first); next_0, next_1: the
// first two after it.
inline double JoinRoughness(const Eigen::Vector3d& past_2, const Eigen::Vector3d& past_1,
                            const Eigen::Vector3d& next_0, const Eigen::Vector3d& next_1) {
  return SquaredSecondDifference(past_2, past_1, next_0) + SquaredSecondDifference(past_1, next_0, next_1);
}

}  // namespace mocap

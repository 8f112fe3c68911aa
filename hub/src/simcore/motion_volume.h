// The space a motion occupies and its vertical axis, so virtual cameras can be placed around it
// without assuming Y-up or Z-up (real files use both).
#pragma once

#include <Eigen/Core>

#include "io/marker_trajectories.h"

namespace mocap {

struct MotionVolume {
  Eigen::Vector3d min = Eigen::Vector3d::Zero();
  Eigen::Vector3d max = Eigen::Vector3d::Zero();
  int up_axis = 2;  // 0 = x, 1 = y, 2 = z; the up direction is +axis

  Eigen::Vector3d Center() const { return 0.5 * (min + max); }
  Eigen::Vector3d Up() const { return Eigen::Vector3d::Unit(up_axis); }
};

// No side of a capture volume is longer than this (1 km): beyond it a coordinate is an error (a
// wrong unit, a corrupt value such as 1e308), not a motion cameras can be placed around.
constexpr double kMaxVolumeSideMm = 1e6;

// Bounding box of every present point. Throws std::runtime_error when the motion has no points
// or spans more than kMaxVolumeSideMm on an axis.
// up_axis < 0 detects it with DetectUpAxis (io/marker_trajectories.h), and throws when it
// cannot be detected.
MotionVolume ComputeMotionVolume(const MarkerTrajectories& motion, int up_axis = -1);

}  // namespace mocap

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

// Bounding box of every present point. Throws std::runtime_error when the motion has no points.
// up_axis < 0 detects it with DetectUpAxis (io/marker_trajectories.h), and throws when it
// cannot be detected.
MotionVolume ComputeMotionVolume(const MarkerTrajectories& motion, int up_axis = -1);

}  // namespace mocap

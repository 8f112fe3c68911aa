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

// The axis along which a body is tallest: the median over frames of the spread of the markers
// along each axis. A standing, walking or running person is 1.5-1.9 m tall and at most about
// 1 m wide or deep in any one frame, whatever the distance travelled. Returns -1 when no frame
// has at least three markers.
int DetectUpAxis(const MarkerTrajectories& motion);

// Bounding box of every present point. Throws std::runtime_error when the motion has no points.
// up_axis < 0 detects it (and throws when it cannot be detected).
MotionVolume ComputeMotionVolume(const MarkerTrajectories& motion, int up_axis = -1);

}  // namespace mocap

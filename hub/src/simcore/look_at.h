// A camera aimed at a point: the one look-at of the simulator and of every test scene.
#pragma once

#include <Eigen/Core>

#include "geometry/camera.h"

namespace mocap {

// cam_from_world rotation of a camera at `center` looking at `target` with world `up` above the
// image (OpenCV axes: x right, y down, z forward).
Eigen::Matrix3d LookAtRotation(const Eigen::Vector3d& center, const Eigen::Vector3d& target, const Eigen::Vector3d& up);

// Places *camera at `center` looking at `target` (rotation and translation; intrinsics kept).
void AimCamera(const Eigen::Vector3d& center, const Eigen::Vector3d& target, const Eigen::Vector3d& up, Camera* camera);

}  // namespace mocap

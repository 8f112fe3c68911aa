// Look-at camera poses (see look_at.h).
#include "simcore/look_at.h"

#include <Eigen/Geometry>

namespace mocap {

Eigen::Matrix3d LookAtRotation(const Eigen::Vector3d& center, const Eigen::Vector3d& target, const Eigen::Vector3d& up) {
  const Eigen::Vector3d forward = (target - center).normalized();
  const Eigen::Vector3d right = forward.cross(up).normalized();
  const Eigen::Vector3d down = forward.cross(right);
  Eigen::Matrix3d rotation;
  rotation.row(0) = right.transpose();
  rotation.row(1) = down.transpose();
  rotation.row(2) = forward.transpose();
  return rotation;
}

void AimCamera(const Eigen::Vector3d& center, const Eigen::Vector3d& target, const Eigen::Vector3d& up, Camera* camera) {
  camera->rotation = LookAtRotation(center, target, up);
  camera->translation = -camera->rotation * center;
}

}  // namespace mocap

// Packing of cameras into solver blocks; rotations go through Ceres' own angle-axis helpers so
// that packing and the cost functors agree on the convention.
#include "calib/camera_blocks.h"

#include <ceres/rotation.h>

namespace mocap {

std::array<double, kPoseSize> PoseBlock(const Camera& camera) {
  std::array<double, kPoseSize> pose{};
  // Ceres reads column-major by default; Eigen matrices are column-major too.
  ceres::RotationMatrixToAngleAxis(camera.rotation.data(), pose.data());
  for (int i = 0; i < 3; ++i) pose[3 + i] = camera.translation(i);
  return pose;
}

std::array<double, kIntrinsicsSize> IntrinsicsBlock(const CameraIntrinsics& intrinsics) {
  const auto& d = intrinsics.distortion;
  return {intrinsics.fx, intrinsics.fy, intrinsics.cx, intrinsics.cy, d[0], d[1], d[2], d[3], d[4]};
}

void SetPoseFromBlock(const double* pose, Camera* camera) {
  ceres::AngleAxisToRotationMatrix(pose, camera->rotation.data());
  camera->translation = Eigen::Vector3d(pose[3], pose[4], pose[5]);
}

void SetIntrinsicsFromBlock(const double* block, CameraIntrinsics* intrinsics) {
  intrinsics->fx = block[0];
  intrinsics->fy = block[1];
  intrinsics->cx = block[2];
  intrinsics->cy = block[3];
  for (int i = 0; i < 5; ++i) intrinsics->distortion[i] = block[4 + i];
}

}  // namespace mocap

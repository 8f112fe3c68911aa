// Conversions between the shared Camera type and the flat parameter blocks of the Ceres solves
// (angle-axis pose, 9-value intrinsics), so that every solve packs and unpacks cameras alike.
#pragma once

#include <array>

#include "calib/cost_functions.h"
#include "geometry/camera.h"

namespace mocap {

std::array<double, kPoseSize> PoseBlock(const Camera& camera);
std::array<double, kIntrinsicsSize> IntrinsicsBlock(const CameraIntrinsics& intrinsics);
void SetPoseFromBlock(const double* pose, Camera* camera);
void SetIntrinsicsFromBlock(const double* block, CameraIntrinsics* intrinsics);

}  // namespace mocap

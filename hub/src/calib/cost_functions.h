// Ceres cost functors of the calibration solves, templated for automatic differentiation and
// built through a static Create(). Their gradients are checked against numeric ones in
// cost_functions_test.cc with ceres::GradientChecker.
#pragma once

#include <ceres/autodiff_cost_function.h>
#include <ceres/rotation.h>

#include <Eigen/Core>

#include "geometry/lens.h"

namespace mocap {

// Parameter block layouts shared by the functors and the problem builders.
constexpr int kPoseSize = 6;        // cam_from_world: angle-axis (3), translation (3)
constexpr int kIntrinsicsSize = 9;  // fx fy cx cy k1 k2 p1 p2 k3 (OpenCV lens model)
// Wand pose: centre (3) and unit axis (3) in one block, so that the Schur complement eliminates
// each frame's wand as a whole (centre and axis share every residual).
constexpr int kWandPoseSize = 6;

// Distorted pixel of a point in camera coordinates under the OpenCV model; false behind the
// camera. Shared by every functor; the lens model itself is geometry/lens.h.
template <typename T>
bool ProjectCameraPoint(const T* intrinsics, const T* point_in_cam, T* pixel) {
  if (!(point_in_cam[2] > T(1e-9))) return false;
  const T x = point_in_cam[0] / point_in_cam[2];
  const T y = point_in_cam[1] / point_in_cam[2];
  T xd, yd;
  DistortNormalized(intrinsics + 4, x, y, &xd, &yd);
  pixel[0] = intrinsics[0] * xd + intrinsics[2];
  pixel[1] = intrinsics[1] * yd + intrinsics[3];
  return true;
}

template <typename T>
void TransformToCamera(const T* cam_from_world, const T* point_in_world, T* point_in_cam) {
  ceres::AngleAxisRotatePoint(cam_from_world, point_in_world, point_in_cam);
  point_in_cam[0] += cam_from_world[3];
  point_in_cam[1] += cam_from_world[4];
  point_in_cam[2] += cam_from_world[5];
}

// Pixel residual (projected - observed) of a world point seen by a camera; false behind it.
// The one reprojection error of every functor.
template <typename T>
bool PixelResidual(const T* cam_from_world, const T* intrinsics, const T* point_in_world,
                   const Eigen::Vector2d& observed_px, T* residuals) {
  T point_in_cam[3];
  TransformToCamera(cam_from_world, point_in_world, point_in_cam);
  T pixel[2];
  if (!ProjectCameraPoint(intrinsics, point_in_cam, pixel)) return false;
  residuals[0] = pixel[0] - T(observed_px.x());
  residuals[1] = pixel[1] - T(observed_px.y());
  return true;
}

// Reprojection error of one wand marker. The wand is a rigid segment: centre and unit axis (kept
// on the sphere by a manifold); the marker sits at a fixed offset along the axis, so
// the known wand length holds exactly and fixes the scale of the whole solve.
class WandReprojectionError {
 public:
  WandReprojectionError(const Eigen::Vector2d& observed_px, double offset_mm)
      : observed_px_(observed_px), offset_mm_(offset_mm) {}

  template <typename T>
  bool operator()(const T* cam_from_world, const T* intrinsics, const T* wand_pose, T* residuals) const {
    T point_in_world[3];
    for (int i = 0; i < 3; ++i) point_in_world[i] = wand_pose[i] + T(offset_mm_) * wand_pose[3 + i];
    return PixelResidual(cam_from_world, intrinsics, point_in_world, observed_px_, residuals);
  }

  static ceres::CostFunction* Create(const Eigen::Vector2d& observed_px, double offset_mm) {
    return new ceres::AutoDiffCostFunction<WandReprojectionError, 2, kPoseSize, kIntrinsicsSize, kWandPoseSize>(
        new WandReprojectionError(observed_px, offset_mm));
  }

 private:
  Eigen::Vector2d observed_px_;
  double offset_mm_;
};

// Reprojection error of a known 3D point (control point, L-frame marker) seen by one camera
// whose pose and intrinsics are refined: the non-linear step after the DLT.
class KnownPointReprojectionError {
 public:
  KnownPointReprojectionError(const Eigen::Vector3d& point_in_world, const Eigen::Vector2d& observed_px)
      : point_in_world_(point_in_world), observed_px_(observed_px) {}

  template <typename T>
  bool operator()(const T* cam_from_world, const T* intrinsics, T* residuals) const {
    const T point[3] = {T(point_in_world_.x()), T(point_in_world_.y()), T(point_in_world_.z())};
    return PixelResidual(cam_from_world, intrinsics, point, observed_px_, residuals);
  }

  static ceres::CostFunction* Create(const Eigen::Vector3d& point_in_world, const Eigen::Vector2d& observed_px) {
    return new ceres::AutoDiffCostFunction<KnownPointReprojectionError, 2, kPoseSize, kIntrinsicsSize>(
        new KnownPointReprojectionError(point_in_world, observed_px));
  }

 private:
  Eigen::Vector3d point_in_world_;
  Eigen::Vector2d observed_px_;
};

}  // namespace mocap

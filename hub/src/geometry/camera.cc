// Pinhole camera over the shared lens model (geometry/lens.h): projection, undistortion and back-projected rays.
#include "geometry/camera.h"

#include <cmath>

#include <Eigen/Dense>

#include "geometry/lens.h"

namespace mocap {
bool CameraIntrinsics::HasDistortion() const {
  for (double v : distortion) {
    if (v != 0.0) return true;
  }
  return false;
}

Eigen::Vector3d Camera::CenterInWorld() const { return -rotation.transpose() * translation; }

Eigen::Vector3d Camera::PointInCamera(const Eigen::Vector3d& point_in_world) const {
  return rotation * point_in_world + translation;
}

bool Camera::ProjectToPixel(const Eigen::Vector3d& point_in_world, Eigen::Vector2d* pixel) const {
  const Eigen::Vector3d point_in_cam = PointInCamera(point_in_world);
  if (!(point_in_cam.z() > 1e-9)) return false;
  const Eigen::Vector2d normalized = point_in_cam.head<2>() / point_in_cam.z();
  *pixel = NormalizedToPixel(DistortNormalized(normalized));
  return true;
}

bool Camera::InImage(const Eigen::Vector2d& pixel) const {
  return pixel.x() >= 0.0 && pixel.y() >= 0.0 && pixel.x() < intrinsics.width &&
         pixel.y() < intrinsics.height;
}

Eigen::Vector2d Camera::DistortNormalized(const Eigen::Vector2d& normalized) const {
  return mocap::DistortNormalized(intrinsics.distortion, normalized);
}

Eigen::Vector2d Camera::NormalizedToPixel(const Eigen::Vector2d& distorted_normalized) const {
  return Eigen::Vector2d(intrinsics.fx * distorted_normalized.x() + intrinsics.cx,
                         intrinsics.fy * distorted_normalized.y() + intrinsics.cy);
}

Eigen::Vector2d Camera::UndistortPixel(const Eigen::Vector2d& pixel) const {
  const Eigen::Vector2d target((pixel.x() - intrinsics.cx) / intrinsics.fx,
                               (pixel.y() - intrinsics.cy) / intrinsics.fy);
  if (!intrinsics.HasDistortion()) return target;
  // Gauss-Newton from the distorted point itself; a step is damped back when it would not
  // reduce the residual, which keeps strong barrel lenses from overshooting near the corners.
  Eigen::Vector2d estimate = target;
  Eigen::Matrix2d jacobian;
  double error = (mocap::DistortNormalized(intrinsics.distortion, estimate, &jacobian) - target).squaredNorm();
  for (int iteration = 0; iteration < 50 && error > 1e-30; ++iteration) {
    const Eigen::Vector2d residual = mocap::DistortNormalized(intrinsics.distortion, estimate, &jacobian) - target;
    const Eigen::Vector2d step = jacobian.partialPivLu().solve(residual);
    if (!step.allFinite()) break;
    double scale = 1.0;
    Eigen::Vector2d candidate = estimate - step;
    double candidate_error = (mocap::DistortNormalized(intrinsics.distortion, candidate) - target).squaredNorm();
    while (candidate_error > error && scale > 1e-4) {
      scale *= 0.5;
      candidate = estimate - scale * step;
      candidate_error = (mocap::DistortNormalized(intrinsics.distortion, candidate) - target).squaredNorm();
    }
    if (candidate_error > error) break;
    estimate = candidate;
    error = candidate_error;
  }
  return estimate;
}

Eigen::Vector3d Camera::RayDirectionInWorld(const Eigen::Vector2d& pixel) const {
  const Eigen::Vector2d normalized = UndistortPixel(pixel);
  const Eigen::Vector3d direction_in_cam(normalized.x(), normalized.y(), 1.0);
  return (rotation.transpose() * direction_in_cam).normalized();
}

Eigen::Matrix<double, 3, 4> Camera::ProjectionMatrix() const {
  Eigen::Matrix<double, 3, 4> projection;
  projection.leftCols<3>() = rotation;
  projection.col(3) = translation;
  return projection;
}

const Camera* Rig::Find(uint32_t id) const {
  for (const Camera& camera : cameras) {
    if (camera.id == id) return &camera;
  }
  return nullptr;
}

}  // namespace mocap

// Pinhole camera with the OpenCV lens model (k1 k2 p1 p2 k3), and a rig of cameras. Shared by
// every hub layer that maps between world points and pixels: recon, calib, sim and eval.
// Pure value types and functions: no I/O, no exceptions except from Eigen asserts.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

namespace mocap {

struct CameraIntrinsics {
  int width = 0;
  int height = 0;
  double fx = 0.0;
  double fy = 0.0;
  double cx = 0.0;
  double cy = 0.0;
  // OpenCV order: k1 k2 p1 p2 k3.
  std::array<double, 5> distortion = {0.0, 0.0, 0.0, 0.0, 0.0};

  bool HasDistortion() const;
};

struct Camera {
  uint32_t id = 0;
  CameraIntrinsics intrinsics;
  // cam_from_world: x_cam = rotation * x_world + translation (OpenCV convention).
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();
  // Centroid noise: RMS length (px) of this camera's reprojection errors in the calibration
  // that placed it (the wand solve's residuals; 2 px on a webcam, 0.05 on a machine-vision
  // camera). 0: unknown. The reconstruction's gates follow it (recon/rig_noise.h).
  double centroid_rms_px = 0.0;

  Eigen::Vector3d CenterInWorld() const;
  Eigen::Vector3d PointInCamera(const Eigen::Vector3d& point_in_world) const;

  // Distorted pixel of a world point. Returns false (pixel untouched) when the point is not
  // strictly in front of the camera. Points outside the image still project; callers that need
  // visibility check InImage().
  bool ProjectToPixel(const Eigen::Vector3d& point_in_world, Eigen::Vector2d* pixel) const;
  bool InImage(const Eigen::Vector2d& pixel) const;

  // Applies the lens model (geometry/lens.h) to normalized (undistorted) image coordinates.
  Eigen::Vector2d DistortNormalized(const Eigen::Vector2d& normalized) const;
  Eigen::Vector2d NormalizedToPixel(const Eigen::Vector2d& distorted_normalized) const;
  // Pixel (distorted) to undistorted normalized image coordinates: the iterative inverse of
  // DistortNormalized (Gauss-Newton with the analytic Jacobian, converges to ~1e-12 for any
  // realistic lens).
  Eigen::Vector2d UndistortPixel(const Eigen::Vector2d& pixel) const;
  // Unit direction, in world coordinates, of the ray from the centre through the pixel.
  Eigen::Vector3d RayDirectionInWorld(const Eigen::Vector2d& pixel) const;
  // Normalized projection matrix [R|t]: maps homogeneous world points to homogeneous
  // undistorted normalized image coordinates (use with UndistortPixel output).
  Eigen::Matrix<double, 3, 4> ProjectionMatrix() const;
};

struct Rig {
  std::vector<Camera> cameras;

  // nullptr when no camera has this id.
  const Camera* Find(uint32_t id) const;
};

}  // namespace mocap

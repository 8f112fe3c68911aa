// Seed 000 section 3.1: the 11-parameter Direct Linear Transformation from known 3D control
// points and their image points (at least 6, not coplanar), decomposed into the OpenCV camera
// model and optionally refined non-linearly (pose, focal lengths, principal point, and lens
// distortion when asked, which takes the place of the seed's optional L12-L16 terms).
#pragma once

#include <array>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "geometry/camera.h"

namespace mocap {

struct ControlPoint {
  Eigen::Vector3d point_in_world = Eigen::Vector3d::Zero();
  Eigen::Vector2d pixel = Eigen::Vector2d::Zero();
};

struct DltOptions {
  uint32_t camera_id = 1;
  int width = 0;   // image size written to the calibration; required (> 0)
  int height = 0;
  bool refine = true;              // non-linear refinement after the linear solve
  bool refine_distortion = false;  // also k1, k2, p1, p2 (needs well-spread points)

  void Check() const;
};

struct DltResult {
  // u = (L1 x + L2 y + L3 z + L4) / (L9 x + L10 y + L11 z + 1), v likewise with L5..L8.
  std::array<double, 11> parameters{};
  double linear_rms_px = 0.0;  // of the 11-parameter model itself
  double skew_px = 0.0;        // skew of the decomposed intrinsics, dropped by the OpenCV model
  Camera camera;
  double camera_rms_px = 0.0;  // of the final camera (after refinement when asked)
};

// Throws std::invalid_argument with the reason for fewer than 6 points, coplanar or otherwise
// degenerate configurations, and options that fail Check().
DltResult CalibrateDlt(const std::vector<ControlPoint>& points, const DltOptions& options);

// Projects with the 11 DLT parameters.
Eigen::Vector2d ProjectDlt(const std::array<double, 11>& parameters, const Eigen::Vector3d& point_in_world);

// Control points as text, one "x y z u v" per line (mm, px), '#' starts a comment, blank lines
// ignored: the five-tuples of seed 000's calibration tool. Throws std::runtime_error naming
// file and line on malformed input.
std::vector<ControlPoint> ReadControlPoints(const std::string& path);

}  // namespace mocap

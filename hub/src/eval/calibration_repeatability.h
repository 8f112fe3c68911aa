// Repeated calibrations of one rig (seed 004 section 4: ten calibrations per placement, the mean
// and standard deviation of each camera's translation and angles): per camera the mean and
// standard deviation of its centre and of its rotation. Each calibration's world frame may
// differ by a rigid motion (a wand calibration's world is its reference camera), so each is
// first aligned onto the reference (the truth when given, else the first calibration) by a
// rigid fit of the camera centres.
// Pure function; throws std::invalid_argument when fewer than two calibrations are given, when
// a calibration shares fewer than three cameras with the reference (alignment), or when no
// camera appears in two calibrations.
#pragma once

#include <cstdint>
#include <limits>
#include <vector>

#include <Eigen/Core>

#include "geometry/camera.h"

namespace mocap {

struct CameraRepeatability {
  uint32_t id = 0;
  size_t calibrations = 0;                              // calibrations holding this camera
  Eigen::Vector3d centre_mean_mm = Eigen::Vector3d::Zero();  // in the reference's world
  Eigen::Vector3d centre_std_mm = Eigen::Vector3d::Zero();   // sample standard deviation per axis
  double centre_spread_mm = 0.0;     // root mean square distance of the centres from their mean
  // Mean rotation (chordal mean: the rotation nearest the sum of the matrices), as the camera's
  // orientation in the world: x-y-z Euler angles of world_from_cam, degrees.
  Eigen::Vector3d euler_mean_deg = Eigen::Vector3d::Zero();
  // Sample standard deviation of each rotation's deviation from the mean, about the camera's
  // own x, y and z axes (a small-angle rotation vector), degrees.
  Eigen::Vector3d rotation_std_deg = Eigen::Vector3d::Zero();
  double rotation_spread_deg = 0.0;  // root mean square angle of the rotations from their mean
  // Against the truth (NaN without one): the mean's centre and rotation error.
  double centre_bias_mm = std::numeric_limits<double>::quiet_NaN();
  double rotation_bias_deg = std::numeric_limits<double>::quiet_NaN();
};

struct CalibrationRepeatability {
  size_t calibrations = 0;
  bool aligned = false;
  bool against_truth = false;
  std::vector<CameraRepeatability> cameras;  // reference order; cameras in two or more calibrations
  double centre_spread_max_mm = 0.0;
  double rotation_spread_max_deg = 0.0;
};

// `truth` may be null (the first calibration is then the reference).
CalibrationRepeatability EvaluateRepeatability(const std::vector<Rig>& calibrations, const Rig* truth, bool align);

}  // namespace mocap

// Running reprojection RMS for the wand solver's report, under the hub's one definition of
// rms_px: root mean square over observations of the 2-D reprojection error length (as recon
// reports per marker and OpenCV per calibration). An observation whose point lies behind its camera has no projection: it is counted
// apart instead of entering the sum with an undefined pixel.
#pragma once

#include <cstddef>

#include <Eigen/Core>

#include "geometry/camera.h"

namespace mocap {

struct ReprojectionSum {
  double squared_px = 0.0;
  size_t observations = 0;
  size_t unprojected = 0;  // observations left out because the point is behind the camera

  // Adds one observed pixel of `point_in_world`; returns false (and counts it) when the point
  // does not project.
  bool Add(const Camera& camera, const Eigen::Vector3d& point_in_world, const Eigen::Vector2d& observed);
  // Root mean square of the error length over observations, 0 without observations.
  double RmsPx() const;
};

}  // namespace mocap

// Running reprojection error per coordinate (the calib layer's rms_px) for the wand solver's
// report. An observation whose point lies behind its camera has no projection: it is counted
// apart instead of entering the sum with an undefined pixel.
#pragma once

#include <cstddef>

#include <Eigen/Core>

#include "geometry/camera.h"

namespace mocap {

struct ReprojectionSum {
  double squared_px = 0.0;
  size_t coordinates = 0;
  size_t unprojected = 0;  // observations left out because the point is behind the camera

  // Adds one observed pixel of `point_in_world`; returns false (and counts it) when the point
  // does not project.
  bool Add(const Camera& camera, const Eigen::Vector3d& point_in_world, const Eigen::Vector2d& observed);
  // Root mean square per coordinate, 0 without observations.
  double RmsPx() const;
};

}  // namespace mocap

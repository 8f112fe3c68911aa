// Linear multi-view triangulation of one point from undistorted normalized image coordinates.
// Calibration needs it before any reconstruction layer is trusted: to start the bundle
// adjustment, to measure wand lengths independently of the solve, and to locate L-frames.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "geometry/camera.h"

namespace mocap {

// One view of a point: the camera's normalized projection matrix [R|t] and the undistorted
// normalized coordinates observed there.
struct PointView {
  Eigen::Matrix<double, 3, 4> cam_from_world;
  Eigen::Vector2d normalized;
};

// Linear (DLT) estimate refined by Gauss-Newton on the normalized reprojection error.
// Returns false when fewer than two views are given or the rays are (nearly) parallel, so that
// the point is not determined; *point_in_world is left untouched then.
bool TriangulateLinear(const std::vector<PointView>& views, Eigen::Vector3d* point_in_world);

// Root mean square reprojection error in pixels of point_in_world over pixel observations.
double ReprojectionRmsPx(const std::vector<const Camera*>& cameras,
                         const std::vector<Eigen::Vector2d>& pixels, const Eigen::Vector3d& point_in_world);

}  // namespace mocap

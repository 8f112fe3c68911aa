// Fast undistortion of blob centroids for one camera: a coarse table of undistorted normalized
// coordinates (exact, from Camera::UndistortPixel) interpolated bilinearly, then one Newton step
// on the shared lens model (geometry/lens.h). Every blob of every frame is undistorted, and the iterative inverse
// from scratch costs several times more than this; the result agrees to under 1e-5 px.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "geometry/camera.h"

namespace mocap {

class Undistorter {
 public:
  // Keeps a reference to the camera. step_px: table spacing.
  explicit Undistorter(const Camera& camera, int step_px = 16);

  // Undistorted normalized coordinates of a (distorted) pixel.
  Eigen::Vector2d Undistort(const Eigen::Vector2d& pixel) const;

 private:
  const Camera* camera_;
  bool distorted_ = false;
  double step_ = 16.0;
  double origin_ = 0.0;  // table covers [origin, origin + step * (cols - 1)] in x and y
  int cols_ = 0;
  int rows_ = 0;
  std::vector<Eigen::Vector2d> table_;
};

}  // namespace mocap

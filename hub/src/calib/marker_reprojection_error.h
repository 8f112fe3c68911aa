// Ceres cost functor of continuous calibration: a marker of an ordinary capture is an unknown
// point (3 values) seen by a camera whose pose may be refined; intrinsics are a constant block.
// Its gradient is checked with ceres::GradientChecker in extrinsic_refinement_test.cc.
#pragma once

#include <ceres/autodiff_cost_function.h>

#include <Eigen/Core>

#include "calib/cost_functions.h"

namespace mocap {

class MarkerReprojectionError {
 public:
  explicit MarkerReprojectionError(const Eigen::Vector2d& observed_px) : observed_px_(observed_px) {}

  template <typename T>
  bool operator()(const T* cam_from_world, const T* intrinsics, const T* point_in_world, T* residuals) const {
    return PixelResidual(cam_from_world, intrinsics, point_in_world, observed_px_, residuals);
  }

  static ceres::CostFunction* Create(const Eigen::Vector2d& observed_px) {
    return new ceres::AutoDiffCostFunction<MarkerReprojectionError, 2, kPoseSize, kIntrinsicsSize, 3>(
        new MarkerReprojectionError(observed_px));
  }

 private:
  Eigen::Vector2d observed_px_;
};

}  // namespace mocap

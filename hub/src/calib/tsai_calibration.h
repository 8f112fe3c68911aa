// Seed 000 section 3.2: Tsai's calibration of one camera from known control points, coplanar
// (a single target face) or not (the folded target), from one view or several views of the
// target that the camera took (the camera or the target moved between them):
//   stages 1-5, the linear solve of each view (tsai_linear.h);
//   stage 6, the non-linear refinement (3.2.12) with Ceres, all of Tsai's parameters jointly
//   from the linear start: every view's pose, and the intrinsics the views share: f, kappa1,
//   the image centre and sx (sx only when a view is not coplanar: coplanar points cannot
//   give it). The error minimised is the reprojection error in the image, in pixels, through
//   Tsai's exact model (kappa1 maps distorted to undistorted sensor coordinates, inverted per
//   point by Newton's method), with a Huber loss against the odd mispaired point.
// Whether the points determine kappa1 is judged from the fit's covariance: kappa1's standard
// deviation, as the displacement it makes at the image corner, must be within
// max_kappa1_corner_sigma_px; a target that covers too little of the image (Willson and the
// seed: spread the points over the whole image) leaves kappa1 undetermined, which the result
// says with the reason (or, with require_kappa1, the calibration is refused).
// The result is Willson's 19-value block (tsai.h) with the first view's pose and its OpenCV
// camera (CameraFromTsai). Error policy: options Check() and unusable point sets throw
// std::invalid_argument naming the rule and what to do.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "calib/dlt.h"
#include "calib/tsai.h"

namespace mocap {

struct TsaiCalibrationOptions {
  uint32_t camera_id = 1;
  int width = 0;            // image size (px); required
  int height = 0;
  double pixel_mm = 0.005;  // sensor cell size (dx = dy = dpx = dpy), mm
  double sx = 1.0;          // the x scale factor for coplanar points (not estimable from them)
  bool refine = true;       // the non-linear stage (6)
  bool refine_centre = true;  // the image centre (Cx, Cy) in the non-linear stage
  int max_iterations = 200;
  double huber_px = 1.0;    // the loss's scale: points off by more count linearly
  double max_rms_px = 5.0;  // a worse final fit is refused (points paired wrongly, or not one camera)
  // kappa1 counts as determined when one standard deviation of it moves the image corner by at
  // most this much (px).
  double max_kappa1_corner_sigma_px = 0.1;
  bool require_kappa1 = false;  // refuse, instead of reporting, an undetermined kappa1

  void Check() const;
};

struct TsaiCalibrationResult {
  TsaiCamera tsai;            // Willson's block, the first view's pose
  TsaiCamera linear;          // the first view after stage 5 (kappa1 0)
  std::vector<TsaiCamera> views;  // every view's camera (shared intrinsics, own pose)
  bool coplanar = false;      // every view's points lie in one plane
  double linear_rms_px = 0.0;  // reprojection RMS of the linear estimates (all views)
  double rms_px = 0.0;        // of the final Tsai model (exact projection, all views)
  // kappa1's standard deviation (1/mm^2) from the fit, and the displacement it makes at the
  // image corner farthest from the centre (px); how far the points reach from the image centre
  // towards that corner (0..1).
  double kappa1_sigma = 0.0;
  double kappa1_corner_sigma_px = 0.0;
  double coverage = 0.0;
  bool kappa1_determined = false;
  std::string kappa1_note;    // why kappa1 is undetermined (empty when it is determined)
  TsaiConversion camera;      // the OpenCV camera (first view's pose) and its fit error
};

// At least 7 points (5 when coplanar) well spread over the image. Throws std::invalid_argument
// with the reason (too few, collinear, origin-free degenerate sets, a solve that ends behind the
// camera).
TsaiCalibrationResult CalibrateTsai(const std::vector<ControlPoint>& points, const TsaiCalibrationOptions& options);
// Several views of the target by the same camera: the intrinsics shared, a pose per view.
TsaiCalibrationResult CalibrateTsaiViews(const std::vector<std::vector<ControlPoint>>& views,
                                         const TsaiCalibrationOptions& options);

}  // namespace mocap

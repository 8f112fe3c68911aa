// Seed 000 section 3.2: Tsai's calibration of one camera from known control points, coplanar
// (a single target face) or not (the folded target), as a multi-stage solve:
//   1. the radial alignment constraint (3.17-3.18): x'/y' = s (r1 x + r2 y + r3 z + tx) /
//      (r4 x + r5 y + r6 z + ty) is linear in 8 unknowns (6 for coplanar points), solved as a
//      homogeneous system (SVD, so no unknown has to be non-zero, unlike the seed's ty = 1);
//   2. the scale from the unit rows of R (3.19; for coplanar points the larger root of 3.21)
//      and the x scale factor s (not for coplanar points);
//   3. the sign: the farthest point from the image centre must lie in its own quadrant; for
//      coplanar points r13 r23 = -(r11 r21 + r12 r22) leaves two sign choices, the one whose
//      back-projection agrees with the image (the seed's sum of x_I x_P + y_I y_P > 0) is kept;
//   4. orthonormalisation of the first two rows (3.2.8: a' = a + k b, b' = b + k a with
//      k = -a.b / 2, normalised), the third row their cross product;
//   5. f and tz by least squares from the projection equations (3.2.11);
//   6. non-linear refinement (3.2.12) with Ceres: pose, f, kappa1, the image centre and s
//      (not for coplanar points) minimising the error in the undistorted sensor plane, scaled
//      to pixels (Willson's choice: Tsai's kappa1 maps distorted to undistorted coordinates).
// The result is Willson's 19-value block (tsai.h) and its OpenCV camera (CameraFromTsai).
// Error policy: options Check() and unusable point sets throw std::invalid_argument naming the
// rule and what to do.
#pragma once

#include <cstdint>
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
  double max_rms_px = 5.0;  // a worse final fit is refused (points paired wrongly, or not one camera)

  void Check() const;
};

struct TsaiCalibrationResult {
  TsaiCamera tsai;            // Willson's block
  TsaiCamera linear;          // after stage 5 (kappa1 0)
  bool coplanar = false;
  double linear_rms_px = 0.0;  // reprojection RMS of the linear estimate
  double rms_px = 0.0;        // of the final Tsai model (exact projection)
  TsaiConversion camera;      // the OpenCV camera and its fit error
};

// At least 7 points (5 when coplanar) well spread over the image. Throws std::invalid_argument
// with the reason (too few, collinear, origin-free degenerate sets, a solve that ends behind the
// camera).
TsaiCalibrationResult CalibrateTsai(const std::vector<ControlPoint>& points, const TsaiCalibrationOptions& options);

}  // namespace mocap

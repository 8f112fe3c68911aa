// Seed 000 section 3.2, stages 1-5 of Tsai's method for one view of known control points:
//   1. the radial alignment constraint (3.17-3.18): x'/y' = s (r1 x + r2 y + r3 z + tx) /
//      (r4 x + r5 y + r6 z + ty) is linear in 8 unknowns (6 for coplanar points), solved as a
//      homogeneous system (SVD, so no unknown has to be non-zero, unlike the seed's ty = 1);
//   2. the scale from the unit rows of R (3.19; for coplanar points the larger root of 3.21)
//      and the x scale factor s (not for coplanar points);
//   3. the sign: for coplanar points r13 r23 = -(r11 r21 + r12 r22) leaves two sign choices
//      besides the overall one; the one whose back-projection agrees with the image (the seed's
//      sum of x_I x_P + y_I y_P > 0, all points in front) is kept;
//   4. orthonormalisation of the first two rows (3.2.8: a' = a + k b, b' = b + k a with
//      k = -a.b / 2, normalised), the third row their cross product;
//   5. f and tz by least squares from the projection equations (3.2.11).
// The image centre is the middle of the image and kappa1 is 0 here; the non-linear stage
// (tsai_calibration.h) refines everything. Error policy: unusable point sets throw
// std::invalid_argument naming the rule and what to do.
#pragma once

#include <vector>

#include "calib/dlt.h"
#include "calib/tsai.h"

namespace mocap {

struct TsaiCalibrationOptions;

struct TsaiLinearView {
  TsaiCamera camera;  // kappa1 0, centre at the image middle
  bool coplanar = false;
};

// At least 7 points (5 when coplanar), not collinear.
TsaiLinearView TsaiLinearStage(const std::vector<ControlPoint>& points, const TsaiCalibrationOptions& options);

}  // namespace mocap

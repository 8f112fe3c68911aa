// Control points of seed 000's square target (calibration_target.h) in one camera image: dark
// squares by Otsu threshold and contours (quadrilaterals with their holes), each face found by
// its holed first square (one hole: wall, two: floor; the holes lie on the diagonal from corner
// 0, checked through the square's own homography so that a slanted view cannot swap corners), the
// face's grid grown outwards ring by ring with a homography refitted on every matched square,
// and every matched corner placed by the Harris response (OpenCV cornerHarris: the strongest
// response near the quadrilateral's corner, as seed 000 section 3.3.2 does) and refined to
// sub-pixel with cornerSubPix. The result is "x y z u v" control points for `calibrate dlt`.
//
// Pure function of the image. Error policy: options Check() throws std::invalid_argument; an
// image in which a face's holed square or enough points cannot be found throws
// std::runtime_error saying what was seen and what to do.
#pragma once

#include <string>
#include <vector>

#include <opencv2/core/mat.hpp>

#include "calib/calibration_target.h"
#include "calib/dlt.h"

namespace mocap {

struct TargetDetectionOptions {
  double min_square_px = 8.0;   // smaller quadrilaterals (side, px) are not squares of the target
  double harris_k = 0.04;       // Harris detector's k
  int harris_block = 3;         // neighbourhood of the Harris structure tensor, px
  double match_gate = 0.3;      // a predicted square matches a detected one within this x pitch
  int min_points_per_face = 12; // fewer found on a face: refused

  void Check() const;
};

struct TargetDetection {
  std::vector<ControlPoint> points;  // in point-index order
  std::vector<int> indices;          // CalibrationTargetLayout point index of each
  int squares_seen = 0;              // dark quadrilaterals in the image
  int wall_points = 0;
  int floor_points = 0;
  double max_harris_shift_px = 0.0;  // largest cornerSubPix move from the Harris maximum
};

// gray: 8-bit single-channel image. Throws as the file comment says.
TargetDetection DetectTargetPoints(const cv::Mat& gray, const CalibrationTargetLayout& layout,
                                   const TargetDetectionOptions& options = TargetDetectionOptions());

// "x y z u v" lines (mm, px) with a comment header: the format ReadControlPoints reads.
void WriteControlPoints(const std::vector<ControlPoint>& points, const std::string& path,
                        const std::string& comment);

}  // namespace mocap

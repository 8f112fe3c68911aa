// Calibration accuracy against a ground-truth rig (DESIGN.md metrics): camera centre error (mm),
// rotation error (deg), scale error, focal length error and the reprojection RMS the calibration
// reported. The result's world frame may differ from the truth's by a rigid motion (a wand
// calibration's world is its reference camera), so by default it is aligned first by a rigid
// fit of the camera centres.
#pragma once

#include <cstdint>
#include <limits>
#include <map>
#include <string>
#include <vector>

#include "geometry/camera.h"

namespace mocap {

struct CalibrationEvalOptions {
  bool align = true;  // false: compare in the result's own world frame (world-frame checks)
};

struct CameraCalibrationError {
  uint32_t id = 0;
  double centre_error_mm = 0.0;
  double rotation_error_deg = 0.0;
  double focal_error_percent = 0.0;  // mean of fx and fy, signed
  double reprojection_rms_px = std::numeric_limits<double>::quiet_NaN();  // as reported; NaN if not
};

struct CalibrationEval {
  std::vector<CameraCalibrationError> cameras;  // cameras present in both, in truth order
  std::vector<uint32_t> missing;                // truth cameras absent from the result
  bool aligned = false;
  // Size of the result relative to the truth minus one (similarity fit of camera centres): the
  // calibration's metric scale error; +0.001 means distances come out 0.1 % too long.
  double scale_error = 0.0;
  double centre_rms_mm = 0.0;
  double centre_max_mm = 0.0;
  double rotation_rms_deg = 0.0;
  double rotation_max_deg = 0.0;
  double reprojection_rms_px = std::numeric_limits<double>::quiet_NaN();  // mean of reported values
};

// reported_rms_px maps camera id to the reprojection RMS the calibration wrote (may be empty).
// Throws std::invalid_argument when fewer than one camera matches, or when alignment is asked
// for with fewer than three matched cameras or collinear centres.
CalibrationEval EvaluateCalibration(const Rig& truth, const Rig& result,
                                    const std::map<uint32_t, double>& reported_rms_px,
                                    const CalibrationEvalOptions& options);

// The per-camera "reprojection_rms_px" fields a calibration JSON may carry (calibrate wand writes
// them); cameras without one, and entries that are not a camera's, are absent. Throws std::runtime_error naming the file when it
// cannot be read or parsed.
std::map<uint32_t, double> ReadReportedReprojectionRms(const std::string& path);

}  // namespace mocap

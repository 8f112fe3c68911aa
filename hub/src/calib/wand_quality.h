// A per-camera quality rating of a wand calibration, as Motive and QTM give one: a word from
// Exceptional to Poor, decided by named thresholds on the two figures operators read, the
// camera's reprojection RMS (px, the hub's rms_px) and the RMS error of the wand length
// triangulated in the frames the camera took part in (mm). The worse of the two decides.
//
// Threads: none. Error policy: Check() throws std::invalid_argument.
#pragma once

#include <array>
#include <string>

#include <nlohmann/json.hpp>

#include "calib/wand_calibration.h"

namespace mocap {

enum class CalibrationRating { kExceptional = 0, kExcellent, kGood, kFair, kPoor };

const char* CalibrationRatingName(CalibrationRating rating);

struct RatingThresholds {
  // Upper limits for Exceptional, Excellent, Good and Fair; anything above the last is Poor.
  // Centroid noise of 0.1-0.15 px per coordinate (a well-focused, well-exposed marker) gives
  // 0.15-0.2 px; the wand length error grows with distance and shrinks with resolution.
  std::array<double, 4> rms_px = {0.20, 0.30, 0.50, 1.00};
  std::array<double, 4> wand_length_rms_mm = {0.50, 1.00, 2.00, 4.00};

  // Throws std::invalid_argument unless both lists are positive and increasing.
  void Check() const;
  nlohmann::json ToJson() const;
};

struct CameraRating {
  CalibrationRating rating = CalibrationRating::kPoor;
  CalibrationRating by_rms = CalibrationRating::kPoor;
  CalibrationRating by_wand_length = CalibrationRating::kPoor;
  // "reprojection RMS" or "wand length error": the figure that decided (the RMS on a tie).
  std::string limited_by;
};

CameraRating RateFigures(double rms_px, double wand_length_rms_mm, const RatingThresholds& thresholds);
// A refused camera is Poor whatever its figures.
CameraRating RateCamera(const CameraCalibrationReport& camera, const RatingThresholds& thresholds);
// The rig as a whole, from its overall figures.
CameraRating RateRig(const WandCalibrationResult& result, const RatingThresholds& thresholds);

}  // namespace mocap

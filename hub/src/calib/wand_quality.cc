// Quality ratings of a wand calibration (see wand_quality.h).
#include "calib/wand_quality.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace mocap {
namespace {

CalibrationRating RateOne(double value, const std::array<double, 4>& limits) {
  if (!std::isfinite(value)) return CalibrationRating::kPoor;
  for (size_t i = 0; i < limits.size(); ++i)
    if (value <= limits[i]) return static_cast<CalibrationRating>(i);
  return CalibrationRating::kPoor;
}

void CheckIncreasing(const std::array<double, 4>& limits, const char* name) {
  for (size_t i = 0; i < limits.size(); ++i) {
    if (!(limits[i] > 0.0 && std::isfinite(limits[i])) || (i > 0 && !(limits[i] > limits[i - 1])))
      throw std::invalid_argument(std::string(name) + " thresholds must be positive and increasing");
  }
}

nlohmann::json LimitsJson(const std::array<double, 4>& limits) {
  nlohmann::json j = nlohmann::json::object();
  for (size_t i = 0; i < limits.size(); ++i) j[CalibrationRatingName(static_cast<CalibrationRating>(i))] = limits[i];
  return j;
}

}  // namespace

const char* CalibrationRatingName(CalibrationRating rating) {
  switch (rating) {
    case CalibrationRating::kExceptional: return "Exceptional";
    case CalibrationRating::kExcellent: return "Excellent";
    case CalibrationRating::kGood: return "Good";
    case CalibrationRating::kFair: return "Fair";
    case CalibrationRating::kPoor: return "Poor";
  }
  return "Poor";
}

void RatingThresholds::Check() const {
  CheckIncreasing(rms_px, "reprojection RMS");
  CheckIncreasing(wand_length_rms_mm, "wand length error");
}

nlohmann::json RatingThresholds::ToJson() const {
  return {{"reprojection_rms_px", LimitsJson(rms_px)},
          {"wand_length_rms_mm", LimitsJson(wand_length_rms_mm)},
          {"rule", "each rating holds up to its limit; above Fair is Poor; the worse of the two figures decides; "
                   "a refused camera is Poor"}};
}

CameraRating RateFigures(double rms_px, double wand_length_rms_mm, const RatingThresholds& thresholds) {
  CameraRating r;
  r.by_rms = RateOne(rms_px, thresholds.rms_px);
  r.by_wand_length = RateOne(wand_length_rms_mm, thresholds.wand_length_rms_mm);
  r.rating = std::max(r.by_rms, r.by_wand_length);
  r.limited_by = r.by_wand_length > r.by_rms ? "wand length error" : "reprojection RMS";
  return r;
}

CameraRating RateCamera(const CameraCalibrationReport& camera, const RatingThresholds& thresholds) {
  CameraRating r = RateFigures(camera.reprojection_rms_px,
                               camera.wand_length.count ? camera.wand_length.rms_mm : INFINITY, thresholds);
  if (!camera.accepted) {
    r.rating = CalibrationRating::kPoor;
    r.limited_by = "refused";
  }
  return r;
}

CameraRating RateRig(const WandCalibrationResult& result, const RatingThresholds& thresholds) {
  return RateFigures(result.reprojection_rms_px, result.wand_length.count ? result.wand_length.rms_mm : INFINITY,
                     thresholds);
}

}  // namespace mocap

// Calibration ratings: each figure against its named limits, the worse one decides, refused
// cameras are Poor, and bad thresholds are refused.
#include "calib/wand_quality.h"

#include <cmath>
#include <stdexcept>

#include <gtest/gtest.h>

namespace mocap {
namespace {

TEST(WandQuality, TheWorseFigureDecides) {
  const RatingThresholds t;  // rms 0.2/0.3/0.5/1.0 px, wand length 0.5/1/2/4 mm
  CameraRating r = RateFigures(0.15, 0.4, t);
  EXPECT_EQ(r.rating, CalibrationRating::kExceptional);
  r = RateFigures(0.15, 1.5, t);
  EXPECT_EQ(r.by_rms, CalibrationRating::kExceptional);
  EXPECT_EQ(r.by_wand_length, CalibrationRating::kGood);
  EXPECT_EQ(r.rating, CalibrationRating::kGood);
  EXPECT_EQ(r.limited_by, "wand length error");
  r = RateFigures(0.6, 0.4, t);
  EXPECT_EQ(r.rating, CalibrationRating::kFair);
  EXPECT_EQ(r.limited_by, "reprojection RMS");
  EXPECT_EQ(RateFigures(0.30, 0.5, t).rating, CalibrationRating::kExcellent);  // limits are inclusive
  EXPECT_EQ(RateFigures(1.01, 0.1, t).rating, CalibrationRating::kPoor);
  EXPECT_EQ(RateFigures(NAN, 0.1, t).rating, CalibrationRating::kPoor);
}

TEST(WandQuality, ARefusedCameraIsPoorWhateverItsFigures) {
  CameraCalibrationReport camera;
  camera.accepted = false;
  camera.reprojection_rms_px = 0.1;
  camera.wand_length.count = 100;
  camera.wand_length.rms_mm = 0.1;
  EXPECT_EQ(RateCamera(camera, RatingThresholds()).rating, CalibrationRating::kPoor);
  EXPECT_EQ(RateCamera(camera, RatingThresholds()).limited_by, "refused");
  camera.accepted = true;
  EXPECT_EQ(RateCamera(camera, RatingThresholds()).rating, CalibrationRating::kExceptional);
  camera.wand_length.count = 0;  // no wand frames: no length figure to trust
  EXPECT_EQ(RateCamera(camera, RatingThresholds()).rating, CalibrationRating::kPoor);
}

TEST(WandQuality, ThresholdsMustIncreaseAndAreNamedInJson) {
  RatingThresholds t;
  t.Check();
  const nlohmann::json j = t.ToJson();
  EXPECT_DOUBLE_EQ(j["reprojection_rms_px"]["Good"].get<double>(), 0.5);
  EXPECT_DOUBLE_EQ(j["wand_length_rms_mm"]["Fair"].get<double>(), 4.0);
  t.rms_px = {0.2, 0.2, 0.5, 1.0};
  EXPECT_THROW(t.Check(), std::invalid_argument);
  t = RatingThresholds();
  t.wand_length_rms_mm = {-1.0, 1.0, 2.0, 4.0};
  EXPECT_THROW(t.Check(), std::invalid_argument);
  EXPECT_STREQ(CalibrationRatingName(CalibrationRating::kExcellent), "Excellent");
}

}  // namespace
}  // namespace mocap

// Calibration evaluation: a rigidly moved copy of the truth scores zero after alignment; known
// perturbations of one camera show up as exactly that error; scale and missing cameras are
// reported; bad input is refused.
#include "eval/calibration_eval.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "calib/wand_calibration.h"
#include "simcore/projector.h"
#include "simcore/ring_rig.h"
#include "simcore/wand.h"

namespace mocap {
namespace {

Rig TruthRig() {
  Rig rig;
  for (int i = 0; i < 6; ++i) {
    Camera camera;
    camera.id = static_cast<uint32_t>(10 + i);
    camera.intrinsics.fx = camera.intrinsics.fy = 1000.0;
    const double angle = i * M_PI / 3.0;
    const Eigen::Vector3d centre(4000.0 * std::cos(angle), 4000.0 * std::sin(angle), 2000.0 + 300.0 * (i % 2));
    camera.rotation = Eigen::AngleAxisd(angle + 0.3, Eigen::Vector3d(0.1, 0.2, 1.0).normalized()).toRotationMatrix();
    camera.translation = -camera.rotation * centre;
    rig.cameras.push_back(camera);
  }
  return rig;
}

// The same physical cameras described in another world frame: world_b = motion * world_a.
Rig MoveWorld(const Rig& rig, const Eigen::Matrix3d& rotation, const Eigen::Vector3d& translation, double scale = 1.0) {
  Rig moved = rig;
  for (Camera& camera : moved.cameras) {
    const Eigen::Vector3d centre = scale * (rotation * camera.CenterInWorld()) + translation;
    camera.rotation = camera.rotation * rotation.transpose();
    camera.translation = -camera.rotation * centre;
  }
  return moved;
}

TEST(CalibrationEvalTest, RigidlyMovedTruthScoresZero) {
  const Rig truth = TruthRig();
  const Rig result = MoveWorld(truth, Eigen::AngleAxisd(2.0, Eigen::Vector3d(1, -2, 0.5).normalized()).toRotationMatrix(),
                               Eigen::Vector3d(500.0, -3000.0, 120.0));
  const CalibrationEval eval = EvaluateCalibration(truth, result, {}, CalibrationEvalOptions());
  EXPECT_TRUE(eval.aligned);
  EXPECT_EQ(eval.cameras.size(), 6u);
  EXPECT_LT(eval.centre_max_mm, 1e-6);
  EXPECT_LT(eval.rotation_max_deg, 1e-6);
  EXPECT_NEAR(eval.scale_error, 0.0, 1e-12);
  EXPECT_TRUE(std::isnan(eval.reprojection_rms_px));
  // Without alignment the same result is far off.
  CalibrationEvalOptions raw;
  raw.align = false;
  EXPECT_GT(EvaluateCalibration(truth, result, {}, raw).centre_max_mm, 100.0);
}

TEST(CalibrationEvalTest, PerturbationsAndScaleAreMeasured) {
  const Rig truth = TruthRig();
  Rig result = MoveWorld(truth, Eigen::Matrix3d::Identity(), Eigen::Vector3d::Zero(), 1.001);
  const CalibrationEval scaled = EvaluateCalibration(truth, result, {}, CalibrationEvalOptions());
  EXPECT_NEAR(scaled.scale_error, 0.001, 1e-9);
  EXPECT_GT(scaled.centre_max_mm, 1.0);

  result = truth;
  // Turn camera 12 by 0.05 deg about its own centre.
  Camera& camera = result.cameras[2];
  const Eigen::Vector3d centre = camera.CenterInWorld();
  camera.rotation = Eigen::AngleAxisd(0.05 * M_PI / 180.0, Eigen::Vector3d::UnitY()) * camera.rotation;
  camera.translation = -camera.rotation * centre;
  camera.intrinsics.fx = camera.intrinsics.fy = 1010.0;
  CalibrationEvalOptions raw;
  raw.align = false;
  const CalibrationEval eval = EvaluateCalibration(truth, result, {{12, 0.2}, {13, 0.4}}, raw);
  EXPECT_NEAR(eval.cameras[2].rotation_error_deg, 0.05, 1e-9);
  EXPECT_NEAR(eval.cameras[2].focal_error_percent, 1.0, 1e-9);
  EXPECT_LT(eval.cameras[2].centre_error_mm, 1e-9);
  EXPECT_NEAR(eval.rotation_max_deg, 0.05, 1e-9);
  EXPECT_NEAR(eval.reprojection_rms_px, 0.3, 1e-12);
  EXPECT_DOUBLE_EQ(eval.cameras[3].reprojection_rms_px, 0.4);
}

TEST(CalibrationEvalTest, MissingCamerasAndBadInput) {
  const Rig truth = TruthRig();
  Rig result = truth;
  result.cameras.erase(result.cameras.begin() + 1);
  const CalibrationEval eval = EvaluateCalibration(truth, result, {}, CalibrationEvalOptions());
  ASSERT_EQ(eval.missing.size(), 1u);
  EXPECT_EQ(eval.missing[0], 11u);
  EXPECT_EQ(eval.cameras.size(), 5u);

  Rig two = truth;
  two.cameras.resize(2);
  EXPECT_THROW(EvaluateCalibration(truth, two, {}, CalibrationEvalOptions()), std::invalid_argument);
  Rig other;
  other.cameras.push_back(truth.cameras[0]);
  other.cameras[0].id = 99;
  EXPECT_THROW(EvaluateCalibration(truth, other, {}, CalibrationEvalOptions()), std::invalid_argument);
}

// The issue's acceptance check, end to end through the simulator: ring rigs around a person's
// volume with per-camera lens distortion, a waved wand projected with 0.15 px noise, occlusion and
// spurious blobs, calibrated from the true intrinsics, evaluated after rigid alignment.
void ExpectWandCalibrationMeetsTargets(int cameras, int frames, uint64_t seed) {
  MotionVolume person;
  person.min = Eigen::Vector3d(-1000.0, -800.0, 0.0);
  person.max = Eigen::Vector3d(1000.0, 800.0, 1800.0);
  person.up_axis = 2;
  RingRigOptions rig_options;
  rig_options.cameras = cameras;
  rig_options.seed = seed;
  const Rig truth = MakeRingRig(person, rig_options);
  WandMotionOptions wand_options;
  wand_options.frames = frames;
  wand_options.seed = seed;
  const MarkerTrajectories motion = MakeWandMotion(truth, wand_options);
  ProjectOptions faults;
  faults.noise_px = 0.15;
  faults.occlusion = 0.01;
  faults.spurious = 0.5;
  faults.seed = seed;
  FaultyProjector projector(truth, motion.NumMarkers(), faults);
  std::vector<FrameSet> sets;
  std::vector<int> seeing;
  for (size_t f = 0; f < motion.NumFrames(); ++f) {
    FrameSet set;
    set.frame_number = motion.frame_numbers[f];
    set.cameras = projector.Project(set.frame_number, 0, &motion.points[f * motion.NumMarkers()], &seeing);
    sets.push_back(std::move(set));
  }
  const WandCalibrationResult result =
      CalibrateWand(sets, truth, WandGeometry::TwoMarker(wand_options.wand_length_mm), WandCalibrationOptions());
  ASSERT_TRUE(result.AllAccepted());
  std::map<uint32_t, double> reported;
  for (const auto& camera : result.cameras) reported[camera.id] = camera.reprojection_rms_px;
  const CalibrationEval eval = EvaluateCalibration(truth, result.rig, reported, CalibrationEvalOptions());
  EXPECT_EQ(eval.cameras.size(), static_cast<size_t>(cameras));
  EXPECT_LT(eval.centre_max_mm, 1.0);
  EXPECT_LT(eval.rotation_max_deg, 0.03);
  EXPECT_LT(std::abs(eval.scale_error), 5e-4);
  // noise_px is per coordinate; rms_px is over the error length of each observation.
  const double per_observation_noise_px = std::sqrt(2.0) * faults.noise_px;
  EXPECT_LT(result.reprojection_rms_px, 1.2 * per_observation_noise_px);
  for (const auto& camera : eval.cameras) EXPECT_LT(camera.reprojection_rms_px, 1.2 * per_observation_noise_px);
}

TEST(WandCalibrationAccuracyTest, EightCameras) { ExpectWandCalibrationMeetsTargets(8, 2000, 3); }

TEST(WandCalibrationAccuracyTest, SixteenCameras) { ExpectWandCalibrationMeetsTargets(16, 2000, 4); }

TEST(ReportedReprojectionRms, CamerasAreReadAndEntriesThatAreNoCameraSkipped) {
  const std::string path = testing::TempDir() + "/reported_rms.json";
  // 4294967297 would have wrapped onto camera 1, and replaced its figure.
  std::ofstream(path) << R"({"cameras": [{"id": 1, "reprojection_rms_px": 0.25}, {"id": 4294967297,
    "reprojection_rms_px": 9.0}, {"id": -2, "reprojection_rms_px": 1.0}, {"id": 3}, "x"]})";
  const std::map<uint32_t, double> reported = ReadReportedReprojectionRms(path);
  ASSERT_EQ(reported.size(), 1u);
  EXPECT_EQ(reported.at(1), 0.25);
  std::filesystem::remove(path);
  EXPECT_THROW(ReadReportedReprojectionRms(path), std::runtime_error);
}

}  // namespace
}  // namespace mocap

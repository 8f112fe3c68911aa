// Whole wand calibrations on noisy synthetic rigs: accuracy against the truth after a rigid
// alignment, refusal of a camera that hardly saw the wand, three-marker wands, and recovery of
// perturbed focal lengths when intrinsics refinement is on.
#include "calib/wand_calibration.h"

#include <cmath>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "geometry/rigid_fit.h"
#include "simcore/test_scenes.h"

namespace mocap {
namespace {

struct Errors {
  double max_centre_mm = 0.0;
  double max_rotation_deg = 0.0;
  double scale = 1.0;
};

// Compares a result whose world is the reference camera's frame with the truth.
Errors CompareToTruth(const Rig& truth, const Rig& result) {
  std::vector<Eigen::Vector3d> source, target;
  for (const Camera& camera : result.cameras) {
    source.push_back(camera.CenterInWorld());
    target.push_back(truth.Find(camera.id)->CenterInWorld());
  }
  const SimilarityTransform rigid = FitRigid(source, target);
  Errors errors;
  errors.scale = FitSimilarity(source, target).scale;
  for (const Camera& camera : result.cameras) {
    const Camera& expected = *truth.Find(camera.id);
    errors.max_centre_mm =
        std::max(errors.max_centre_mm, (rigid.Apply(camera.CenterInWorld()) - expected.CenterInWorld()).norm());
    // cam_from_truth = cam_from_result * result_from_truth.
    const Eigen::Matrix3d aligned = camera.rotation * rigid.rotation.transpose();
    const double angle = Eigen::AngleAxisd(aligned * expected.rotation.transpose()).angle();
    errors.max_rotation_deg = std::max(errors.max_rotation_deg, angle * 180.0 / M_PI);
  }
  return errors;
}

TEST(WandCalibrationTest, EightCameraRigWithDistortionMeetsAccuracyTargets) {
  const Rig truth = testing::RingRig(8, 11);
  const WandGeometry wand = WandGeometry::TwoMarker(500.0);
  const testing::WandScene scene = testing::MakeWandScene(truth, wand.marker_offsets_mm, 1500, 0.15, 12);
  const WandCalibrationResult result = CalibrateWand(scene.frames, truth, wand, WandCalibrationOptions());
  ASSERT_TRUE(result.AllAccepted());
  ASSERT_EQ(result.rig.cameras.size(), 8u);
  EXPECT_GT(result.frames_used, 0.97 * result.frames_selected);
  const Errors errors = CompareToTruth(truth, result.rig);
  EXPECT_LT(errors.max_centre_mm, 1.0);
  EXPECT_LT(errors.max_rotation_deg, 0.03);
  EXPECT_NEAR(errors.scale, 1.0, 5e-4);
  // Per coordinate, the residual of a well-fitted model is the centroid noise.
  EXPECT_LT(result.reprojection_rms_px, 1.2 * std::sqrt(2.0) * 0.15);
  EXPECT_GT(result.reprojection_rms_px, 0.8 * std::sqrt(2.0) * 0.15);
  // Each accepted camera carries its own residual RMS as its centroid noise (calibration JSON).
  for (size_t i = 0; i < result.rig.cameras.size(); ++i) {
    EXPECT_EQ(result.rig.cameras[i].centroid_rms_px, result.cameras[i].reprojection_rms_px);
    EXPECT_GT(result.rig.cameras[i].centroid_rms_px, 0.7 * std::sqrt(2.0) * 0.15);
  }
  EXPECT_LT(std::abs(result.wand_length.mean_mm), 0.1);
  EXPECT_LT(result.wand_length.rms_mm, 1.0);
  for (const CameraCalibrationReport& camera : result.cameras) {
    EXPECT_GT(camera.coverage, 0.3) << camera.id;
    EXPECT_GT(camera.views_used, 500u) << camera.id;
    EXPECT_TRUE(camera.reason.empty());
  }
}

TEST(WandCalibrationTest, ReferenceCameraIsTheMostObservedOne) {
  Rig truth = testing::RingRig(6, 21);
  // Pull camera 4 back and widen it so that it sees the wand more often than any other.
  truth.cameras[3].intrinsics.fx = truth.cameras[3].intrinsics.fy = 600.0;
  const WandGeometry wand = WandGeometry::TwoMarker(400.0);
  const testing::WandScene scene = testing::MakeWandScene(truth, wand.marker_offsets_mm, 800, 0.1, 22);
  const WandCalibrationResult result = CalibrateWand(scene.frames, truth, wand, WandCalibrationOptions());
  size_t most = 0;
  uint32_t most_id = 0;
  for (const auto& camera : result.cameras) {
    if (camera.views_selected > most) {
      most = camera.views_selected;
      most_id = camera.id;
    }
  }
  EXPECT_EQ(result.reference_camera_id, most_id);
  // The reference camera defines the world frame.
  const Camera* reference = result.rig.Find(most_id);
  ASSERT_NE(reference, nullptr);
  EXPECT_LT((reference->rotation - Eigen::Matrix3d::Identity()).norm(), 1e-12);
  EXPECT_LT(reference->translation.norm(), 1e-9);
}

TEST(WandCalibrationTest, CameraThatHardlySawTheWandIsRefusedWithAdvice) {
  Rig truth = testing::RingRig(6, 31);
  // Camera 2 looks up at the ceiling: the wand almost never enters its view.
  truth.cameras[1] = testing::LookAtCamera(2, truth.cameras[1].CenterInWorld(),
                                           truth.cameras[1].CenterInWorld() + Eigen::Vector3d(10.0, 0.0, 1000.0));
  const WandGeometry wand = WandGeometry::TwoMarker(500.0);
  const testing::WandScene scene = testing::MakeWandScene(truth, wand.marker_offsets_mm, 800, 0.15, 32);
  const WandCalibrationResult result = CalibrateWand(scene.frames, truth, wand, WandCalibrationOptions());
  EXPECT_FALSE(result.AllAccepted());
  EXPECT_FALSE(result.cameras[1].accepted);
  EXPECT_NE(result.cameras[1].reason.find("wave the wand more in camera 2"), std::string::npos)
      << result.cameras[1].reason;
  EXPECT_EQ(result.rig.cameras.size(), 5u);
  EXPECT_EQ(result.rig.Find(2), nullptr);
  const Errors errors = CompareToTruth(truth, result.rig);
  EXPECT_LT(errors.max_centre_mm, 2.0);
}

TEST(WandCalibrationTest, CameraWithWrongIntrinsicsIsRefusedAsABadSolve) {
  const Rig truth = testing::RingRig(8, 35);
  Rig intrinsics = truth;
  // Camera 5's entry in the intrinsics file belongs to another lens: 12 % longer focal length.
  intrinsics.cameras[4].intrinsics.fx *= 1.12;
  intrinsics.cameras[4].intrinsics.fy *= 1.12;
  const WandGeometry wand = WandGeometry::TwoMarker(500.0);
  const testing::WandScene scene = testing::MakeWandScene(truth, wand.marker_offsets_mm, 1000, 0.15, 36);
  const WandCalibrationResult result = CalibrateWand(scene.frames, intrinsics, wand, WandCalibrationOptions());
  EXPECT_FALSE(result.cameras[4].accepted);
  EXPECT_NE(result.cameras[4].reason.find("check camera 5's intrinsics"), std::string::npos)
      << result.cameras[4].reason;
  for (size_t i = 0; i < result.cameras.size(); ++i) {
    if (i != 4) {
      EXPECT_TRUE(result.cameras[i].accepted) << result.cameras[i].reason;
    }
  }
  // The others were solved again without it and keep their accuracy.
  const Errors errors = CompareToTruth(truth, result.rig);
  EXPECT_LT(errors.max_centre_mm, 1.0);
  EXPECT_LT(errors.max_rotation_deg, 0.03);
}

TEST(WandCalibrationTest, ThreeMarkerWand) {
  const Rig truth = testing::RingRig(8, 41);
  const WandGeometry wand = WandGeometry::ThreeMarker(600.0, 200.0);
  const testing::WandScene scene = testing::MakeWandScene(truth, wand.marker_offsets_mm, 800, 0.15, 42);
  const WandCalibrationResult result = CalibrateWand(scene.frames, truth, wand, WandCalibrationOptions());
  ASSERT_TRUE(result.AllAccepted());
  // The off-centre middle marker must orient every frame's wand: none may be lost to a reversed end order.
  EXPECT_GT(result.frames_used, 0.97 * result.frames_selected);
  const Errors errors = CompareToTruth(truth, result.rig);
  EXPECT_LT(errors.max_centre_mm, 1.0);
  EXPECT_LT(errors.max_rotation_deg, 0.03);
  EXPECT_NEAR(errors.scale, 1.0, 5e-4);
}

TEST(WandCalibrationTest, RefinesPerturbedFocalLengths) {
  const Rig truth = testing::RingRig(8, 51);
  Rig guess = truth;
  for (Camera& camera : guess.cameras) {
    camera.intrinsics.fx *= 1.015;
    camera.intrinsics.fy *= 1.015;
    camera.intrinsics.cx += 4.0;
  }
  const WandGeometry wand = WandGeometry::TwoMarker(500.0);
  const testing::WandScene scene = testing::MakeWandScene(truth, wand.marker_offsets_mm, 1500, 0.15, 52);
  WandCalibrationOptions options;
  options.bundle.refine_intrinsics = IntrinsicsRefinement::kFocalAndPrincipal;
  const WandCalibrationResult result = CalibrateWand(scene.frames, guess, wand, options);
  ASSERT_TRUE(result.AllAccepted());
  for (const Camera& camera : result.rig.cameras) {
    const CameraIntrinsics& expected = truth.Find(camera.id)->intrinsics;
    EXPECT_NEAR(camera.intrinsics.fx / expected.fx, 1.0, 2e-3) << camera.id;
    EXPECT_NEAR(camera.intrinsics.cx, expected.cx, 1.5) << camera.id;
  }
  EXPECT_LT(result.reprojection_rms_px, 1.2 * std::sqrt(2.0) * 0.15);
  // Without refinement the wrong focal lengths show up as residuals the report exposes.
  const WandCalibrationResult fixed = CalibrateWand(scene.frames, guess, wand, WandCalibrationOptions());
  EXPECT_GT(fixed.reprojection_rms_px, 1.5 * result.reprojection_rms_px);
}

TEST(WandCalibrationTest, InvalidOptionsAndEmptyInputThrow) {
  const Rig truth = testing::RingRig(4, 61);
  WandCalibrationOptions options;
  options.min_coverage = 2.0;
  EXPECT_THROW(CalibrateWand({}, truth, WandGeometry::TwoMarker(500.0), options), std::invalid_argument);
  EXPECT_THROW(CalibrateWand({}, truth, WandGeometry::TwoMarker(5.0), WandCalibrationOptions()),
               std::invalid_argument);
  EXPECT_THROW(CalibrateWand({}, truth, WandGeometry::TwoMarker(500.0), WandCalibrationOptions()),
               std::runtime_error);
}

}  // namespace
}  // namespace mocap

// A knocked camera found again from a walking subject: a 10-camera ring with lens distortion,
// 10 s of a synthetic walker (0.15 px noise, 3 % occlusion), one camera turned 0.5, 2 and 5 deg
// and moved 5, 20 and 50 mm; RefineExtrinsics brings it within 0.3 mm and 0.02 deg of its new
// pose and leaves every other camera as it was. The first pose (shift vote, PnP + RANSAC) does
// not need the old pose to be close; a camera whose blobs are gone is refused with what to do.
#include "calib/camera_relocalization.h"

#include <cstdio>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "calib/extrinsic_refinement.h"
#include "simcore/camera_bump.h"
#include "simcore/motion_volume.h"
#include "simcore/projector.h"
#include "simcore/ring_rig.h"
#include "simcore/synthetic_motion.h"

namespace mocap {
namespace {

constexpr uint32_t kKnocked = 4;

MarkerTrajectories TenSecondWalk() {
  SyntheticMotionOptions options;
  options.markers = 41;
  options.rate_hz = 60.0;
  options.frames = 600;
  options.seed = 5;
  return MakeSyntheticMotion(options);
}

Rig TenCameraRig(const MarkerTrajectories& motion) {
  RingRigOptions options;
  options.cameras = 10;
  options.lens_distortion = true;
  return MakeRingRig(ComputeMotionVolume(motion), options);
}

// The capture as `seen_by` sees it, reconstructed with `calibration` into marker samples.
std::unique_ptr<MarkerResidualCollector> Capture(const MarkerTrajectories& motion, const Rig& seen_by,
                                                 const Rig& calibration, uint64_t seed) {
  ProjectOptions project;
  project.noise_px = 0.15;
  project.occlusion = 0.03;
  project.seed = seed;
  FaultyProjector projector(seen_by, motion.NumMarkers(), project);
  auto collector = std::make_unique<MarkerResidualCollector>(calibration, MarkerResidualOptions());
  std::vector<int> seeing;
  for (size_t f = 0; f < motion.NumFrames(); ++f) {
    FrameSet set;
    set.frame_number = motion.frame_numbers[f];
    set.cameras = projector.Project(set.frame_number, 0, &motion.points[f * motion.NumMarkers()], &seeing);
    collector->Add(set);
  }
  return collector;
}

struct Knock {
  double degrees;
  double mm;
};

class KnockTest : public ::testing::TestWithParam<Knock> {};

TEST_P(KnockTest, KnockedCameraIsRecoveredAndTheOthersStay) {
  const Knock knock = GetParam();
  const MarkerTrajectories motion = TenSecondWalk();
  const Rig calibration = TenCameraRig(motion);
  Rig truth = calibration;
  ApplyCameraBump({kKnocked, knock.degrees, knock.mm, 0.0, 9}, &truth);
  const auto collector = Capture(motion, truth, calibration, 21);
  const ExtrinsicRefinement refined =
      RefineExtrinsics(calibration, collector->samples(), collector->blobs(), ExtrinsicRefinementOptions());
  ASSERT_EQ(refined.cameras.size(), calibration.cameras.size());
  for (size_t c = 0; c < calibration.cameras.size(); ++c) {
    const CameraRefinement& camera = refined.cameras[c];
    SCOPED_TRACE("camera " + std::to_string(camera.camera_id));
    if (camera.camera_id != kKnocked) {
      EXPECT_FALSE(camera.refined);
      EXPECT_EQ(refined.rig.cameras[c].rotation, calibration.cameras[c].rotation);
      EXPECT_EQ(refined.rig.cameras[c].translation, calibration.cameras[c].translation);
      continue;
    }
    ASSERT_TRUE(camera.refined);
    EXPECT_TRUE(camera.accepted) << camera.note;
    EXPECT_EQ(camera.state_after, CameraPoseState::kOk);
    const CameraRelocalization& r = camera.relocalization;
    const PoseChange first = ComparePoses(r.camera, truth.cameras[c]);
    const PoseChange error = ComparePoses(refined.rig.cameras[c], truth.cameras[c]);
    std::printf("knock %.1f deg %.0f mm: median %.2f -> %.3f px; shift (%.1f, %.1f) px, %zu candidates, %zu RANSAC "
                "inliers, %zu views; first pose off by %.3f mm %.4f deg, solved %.4f mm %.5f deg\n",
                knock.degrees, knock.mm, camera.before.median_px, camera.after.median_px, r.shift_px.x(),
                r.shift_px.y(), r.candidates, r.ransac_inliers, r.inliers, first.centre_mm, first.rotation_deg,
                error.centre_mm, error.rotation_deg);
    EXPECT_TRUE(r.ok) << r.reason;
    EXPECT_LT(error.centre_mm, 0.3);
    EXPECT_LT(error.rotation_deg, 0.02);
  }
}

INSTANTIATE_TEST_SUITE_P(Knocks, KnockTest, ::testing::Values(Knock{0.5, 5.0}, Knock{2.0, 20.0}, Knock{5.0, 50.0}),
                         [](const ::testing::TestParamInfo<Knock>& info) {
                           return "deg" + std::to_string(static_cast<int>(info.param.degrees * 10)) + "_mm" +
                                  std::to_string(static_cast<int>(info.param.mm));
                         });

TEST(CameraRelocalizationTest, UnknockedRigIsLeftAsItWas) {
  const MarkerTrajectories motion = TenSecondWalk();
  const Rig calibration = TenCameraRig(motion);
  const auto collector = Capture(motion, calibration, calibration, 22);
  const ExtrinsicRefinement refined =
      RefineExtrinsics(calibration, collector->samples(), collector->blobs(), ExtrinsicRefinementOptions());
  EXPECT_FALSE(refined.Changed());
  for (size_t c = 0; c < calibration.cameras.size(); ++c) {
    EXPECT_EQ(refined.cameras[c].state_before, CameraPoseState::kOk) << "camera " << c + 1;
    EXPECT_EQ(refined.rig.cameras[c].rotation, calibration.cameras[c].rotation);
    EXPECT_EQ(refined.rig.cameras[c].translation, calibration.cameras[c].translation);
  }
}

// The first pose alone, from far: the old pose is 5 deg off and its nearest blobs are other
// markers, yet the vote, RANSAC and re-pairing land within a millimetre before any joint solve.
TEST(CameraRelocalizationTest, FirstPoseDoesNotNeedTheOldOne) {
  const MarkerTrajectories motion = TenSecondWalk();
  const Rig calibration = TenCameraRig(motion);
  Rig truth = calibration;
  ApplyCameraBump({kKnocked, 5.0, 50.0, 0.0, 3}, &truth);
  auto collector = Capture(motion, truth, calibration, 23);
  std::vector<char> excluded(calibration.cameras.size(), 0);
  excluded[kKnocked - 1] = 1;
  const CameraRelocalization r = RelocalizeCamera(calibration, kKnocked - 1, excluded, collector->samples(),
                                                  collector->blobs(), CameraRelocalizationOptions());
  ASSERT_TRUE(r.ok) << r.reason;
  const PoseChange error = ComparePoses(r.camera, truth.cameras[kKnocked - 1]);
  EXPECT_LT(error.centre_mm, 1.0);
  EXPECT_LT(error.rotation_deg, 0.02);
  EXPECT_GT(r.shift_px.norm(), 20.0);  // the knock moved the markers far beyond their spacing
  EXPECT_LT(r.median_px, 0.5);

  // Blobs that are not the markers (the camera sees something else): no pose gathers a
  // quarter of the candidates, and the camera is refused with what to do.
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> x(0.0, 1280.0), y(0.0, 800.0);
  for (FrameBlobs& frame : *collector->mutable_blobs()) {
    for (Eigen::Vector2d& blob : frame.pixels[kKnocked - 1]) blob = Eigen::Vector2d(x(rng), y(rng));
  }
  const CameraRelocalization lost = RelocalizeCamera(calibration, kKnocked - 1, excluded, collector->samples(),
                                                     collector->blobs(), CameraRelocalizationOptions());
  EXPECT_FALSE(lost.ok);
  EXPECT_NE(lost.reason.find("calibrate with the wand again"), std::string::npos) << lost.reason;
}

TEST(CameraRelocalizationTest, CameraWithoutBlobsIsRefusedWithWhatToDo) {
  const MarkerTrajectories motion = TenSecondWalk();
  const Rig calibration = TenCameraRig(motion);
  auto collector = Capture(motion, calibration, calibration, 24);
  for (FrameBlobs& frame : *collector->mutable_blobs()) frame.pixels[kKnocked - 1].clear();
  std::vector<char> excluded(calibration.cameras.size(), 0);
  excluded[kKnocked - 1] = 1;
  const CameraRelocalization r = RelocalizeCamera(calibration, kKnocked - 1, excluded, collector->samples(),
                                                  collector->blobs(), CameraRelocalizationOptions());
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.reason.find("camera 4"), std::string::npos) << r.reason;
  EXPECT_NE(r.reason.find("capture the subject"), std::string::npos) << r.reason;
}

TEST(CameraRelocalizationTest, NearestBlobNeedsAnUnambiguousWinner) {
  const std::vector<Eigen::Vector2d> blobs = {{10.0, 0.0}, {0.0, 3.0}, {50.0, 50.0}};
  EXPECT_EQ(UnambiguousNearestBlob(blobs, {0.0, 0.0}, 5.0, 2.0), 1);   // 3 px against 10 px
  EXPECT_EQ(UnambiguousNearestBlob(blobs, {0.0, 0.0}, 2.0, 2.0), -1);  // beyond the gate
  EXPECT_EQ(UnambiguousNearestBlob(blobs, {5.0, 1.5}, 50.0, 1.2), -1); // two blobs at the same distance
  EXPECT_EQ(UnambiguousNearestBlob({}, {0.0, 0.0}, 50.0, 1.0), -1);
}

TEST(CameraRelocalizationTest, OptionsAreChecked) {
  CameraRelocalizationOptions options;
  EXPECT_NO_THROW(options.Check());
  options.search_px = 0.0;
  EXPECT_THROW(options.Check(), std::invalid_argument);
  options = CameraRelocalizationOptions();
  options.vote_bin_px = 0.01;  // a vote grid of 50000 cells a side
  EXPECT_THROW(options.Check(), std::invalid_argument);
  options = CameraRelocalizationOptions();
  options.ambiguity_ratio = 0.5;
  EXPECT_THROW(options.Check(), std::invalid_argument);
  options = CameraRelocalizationOptions();
  options.min_inliers = 3;
  EXPECT_THROW(options.Check(), std::invalid_argument);
  options = CameraRelocalizationOptions();
  options.min_inlier_fraction = 1.0;
  EXPECT_THROW(options.Check(), std::invalid_argument);
}

}  // namespace
}  // namespace mocap

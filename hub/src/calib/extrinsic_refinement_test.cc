// Continuous calibration on simulated captures of a walking subject: a camera bumped by 0.5 deg
// and 5 mm is found within 2 s and solved back onto its true pose from the markers alone; a rig
// that did not move stays exactly as it was, over 10 minutes of capture taken in chunks.
#include "calib/extrinsic_refinement.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "calib/camera_blocks.h"
#include "calib/gradient_check_testing.h"
#include "calib/marker_reprojection_error.h"
#include "io/trc.h"
#include "simcore/camera_bump.h"
#include "simcore/motion_volume.h"
#include "simcore/projector.h"
#include "simcore/ring_rig.h"
#include "simcore/synthetic_motion.h"
#include "simcore/test_scenes.h"

namespace mocap {
namespace {

Rig WalkRig(const MarkerTrajectories& motion) {
  RingRigOptions options;
  options.cameras = 8;
  return MakeRingRig(ComputeMotionVolume(motion), options);
}

// Frame sets of the motion as `seen_by` sees it: centroid noise, short occlusions, merged blobs.
class CaptureSimulator {
 public:
  CaptureSimulator(const Rig& seen_by, size_t markers, uint64_t seed) {
    ProjectOptions options;
    options.noise_px = 0.15;
    options.occlusion = 0.01;
    options.seed = seed;
    projector_ = std::make_unique<FaultyProjector>(seen_by, markers, options);
  }
  FrameSet Frame(const MarkerTrajectories& motion, size_t index) {
    FrameSet set;
    set.frame_number = motion.frame_numbers[index];
    set.cameras = projector_->Project(set.frame_number, 0, &motion.points[index * motion.NumMarkers()], &seeing_);
    return set;
  }

 private:
  std::unique_ptr<FaultyProjector> projector_;
  std::vector<int> seeing_;
};

constexpr uint32_t kBumpedCamera = 3;

TEST(ExtrinsicRefinementTest, BumpFoundWithinTwoSecondsAndSolvedBack) {
  const MarkerTrajectories motion = testing::WalkOrSyntheticWalker(MOCAP_SHARED_DIR);
  const Rig calibration = WalkRig(motion);
  Rig truth = calibration;
  ApplyCameraBump({kBumpedCamera, 0.5, 5.0, 0.0, 7}, &truth);
  const PoseChange bump = ComparePoses(truth.cameras[kBumpedCamera - 1], calibration.cameras[kBumpedCamera - 1]);
  ASSERT_NEAR(bump.rotation_deg, 0.5, 1e-9);
  ASSERT_NEAR(bump.centre_mm, 5.0, 1e-9);

  CaptureSimulator capture(truth, motion.NumMarkers(), 11);
  MarkerResidualCollector collector(calibration, MarkerResidualOptions());
  const size_t two_seconds = static_cast<size_t>(2.0 * motion.rate_hz);
  long detected_at = -1;
  for (size_t f = 0; f < motion.NumFrames(); ++f) {
    collector.Add(capture.Frame(motion, f));
    const BumpDetection detection =
        DetectBumps(ComputeCameraResiduals(calibration, collector.samples()), BumpDetectionOptions());
    for (const CameraVerdict& camera : detection.cameras) {
      // No other camera is ever blamed for the bumped one's residuals.
      if (camera.camera_id != kBumpedCamera) {
        EXPECT_NE(camera.state, CameraPoseState::kBumped) << "frame " << f;
        EXPECT_NE(camera.state, CameraPoseState::kDrifting) << "frame " << f;
      } else if (camera.state == CameraPoseState::kBumped && detected_at < 0) {
        detected_at = static_cast<long>(f);
      }
    }
    if (f + 1 == two_seconds) {
      ASSERT_GE(detected_at, 0) << "not detected within 2 s";
    }
  }
  std::printf("bump detected after %ld frames (%.3f s)\n", detected_at + 1, (detected_at + 1) / motion.rate_hz);

  const ExtrinsicRefinement refined = RefineExtrinsics(calibration, collector.samples(), collector.blobs(), ExtrinsicRefinementOptions());
  ASSERT_TRUE(refined.Changed());
  for (size_t c = 0; c < calibration.cameras.size(); ++c) {
    const CameraRefinement& camera = refined.cameras[c];
    SCOPED_TRACE("camera " + std::to_string(camera.camera_id));
    if (camera.camera_id == kBumpedCamera) {
      EXPECT_EQ(camera.state_before, CameraPoseState::kBumped);
      EXPECT_TRUE(camera.accepted) << camera.note;
      EXPECT_EQ(camera.state_after, CameraPoseState::kOk);
      const PoseChange error = ComparePoses(refined.rig.cameras[c], truth.cameras[c]);
      std::printf("camera %u: residual median %.3f -> %.3f px, solved pose off the truth by %.4f mm, %.5f deg "
                  "(moved %.3f mm, %.4f deg; %zu views, %zu outliers)\n",
                  camera.camera_id, camera.before.median_px, camera.after.median_px, error.centre_mm,
                  error.rotation_deg, camera.centre_change_mm, camera.rotation_change_deg, camera.inlier_views,
                  camera.outlier_views);
      EXPECT_LT(error.centre_mm, 0.5);
      EXPECT_LT(error.rotation_deg, 0.02);
    } else {
      EXPECT_FALSE(camera.refined);
      EXPECT_EQ(refined.rig.cameras[c].rotation, calibration.cameras[c].rotation);
      EXPECT_EQ(refined.rig.cameras[c].translation, calibration.cameras[c].translation);
    }
  }
}

// Ten minutes of a walking subject at 60 Hz in 30 s chunks: no camera is ever flagged and the
// refinement returns the calibration unchanged, bit for bit, chunk after chunk.
TEST(ExtrinsicRefinementTest, UnbumpedRigDoesNotDriftOverTenMinutes) {
  SyntheticMotionOptions motion_options;
  motion_options.markers = 41;
  motion_options.rate_hz = 60.0;
  motion_options.frames = 10 * 60 * 60;
  const MarkerTrajectories motion = MakeSyntheticMotion(motion_options);
  const Rig calibration = WalkRig(motion);
  CaptureSimulator capture(calibration, motion.NumMarkers(), 5);
  const size_t chunk = 30 * 60;
  double worst_median = 0.0;
  for (size_t start = 0; start < motion.NumFrames(); start += chunk) {
    MarkerResidualCollector collector(calibration, MarkerResidualOptions());
    // Every frame is projected (occlusions run on); every third frame set is reconstructed, as
    // serve's monitor samples a high-rate capture.
    for (size_t f = start; f < std::min(start + chunk, motion.NumFrames()); ++f) {
      const FrameSet set = capture.Frame(motion, f);
      if (f % 3 == 0) collector.Add(set);
    }
    const ExtrinsicRefinement refined =
        RefineExtrinsics(calibration, collector.samples(), collector.blobs(), ExtrinsicRefinementOptions());
    EXPECT_FALSE(refined.Changed()) << "chunk at frame " << start;
    for (size_t c = 0; c < calibration.cameras.size(); ++c) {
      EXPECT_EQ(refined.cameras[c].state_before, CameraPoseState::kOk) << "chunk " << start << " camera " << c + 1;
      EXPECT_EQ(refined.rig.cameras[c].rotation, calibration.cameras[c].rotation);
      EXPECT_EQ(refined.rig.cameras[c].translation, calibration.cameras[c].translation);
      worst_median = std::max(worst_median, refined.cameras[c].before.median_px);
    }
  }
  std::printf("10 min unbumped: worst per-camera median residual of a 30 s chunk %.3f px\n", worst_median);
}

TEST(ExtrinsicRefinementTest, TooManyMovedCamerasAreRefused) {
  const MarkerTrajectories motion = testing::WalkOrSyntheticWalker(MOCAP_SHARED_DIR);
  const Rig calibration = WalkRig(motion);
  Rig truth = calibration;
  for (uint32_t id = 1; id <= 7; ++id) ApplyCameraBump({id, 1.0, 10.0, 0.0, id}, &truth);
  CaptureSimulator capture(truth, motion.NumMarkers(), 3);
  MarkerResidualCollector collector(calibration, MarkerResidualOptions());
  for (size_t f = 0; f < 60; ++f) collector.Add(capture.Frame(motion, f));
  BumpDetectionOptions detection;
  detection.baseline_px = 0.2;  // the calibration's own residual: half the rig cannot be the baseline
  ExtrinsicRefinementOptions options;
  options.detection = detection;
  EXPECT_THROW(RefineExtrinsics(calibration, collector.samples(), collector.blobs(), options), std::runtime_error);
}

TEST(ExtrinsicRefinementTest, OptionsAreChecked) {
  ExtrinsicRefinementOptions options;
  options.outlier_px = 0.0;
  EXPECT_THROW(options.Check(), std::invalid_argument);
  options = ExtrinsicRefinementOptions();
  options.detection.bump_px = 0.1;  // below drift_px
  EXPECT_THROW(options.Check(), std::invalid_argument);
  MarkerResidualOptions residuals;
  residuals.ambiguity_ratio = 0.5;
  EXPECT_THROW(residuals.Check(), std::invalid_argument);
}

// The residual's Jacobians at a point `distance_mm` along the pixel's ray, against numeric ones
// with a first step small against the depth (calib/gradient_check_testing.h).
void ExpectGradientMatchesNumeric(const Camera& camera, const Eigen::Vector2d& pixel, double distance_mm) {
  std::array<double, kPoseSize> pose = PoseBlock(camera);
  std::array<double, kIntrinsicsSize> intrinsics = IntrinsicsBlock(camera.intrinsics);
  const Eigen::Vector3d point_in_world = camera.CenterInWorld() + distance_mm * camera.RayDirectionInWorld(pixel);
  std::array<double, 3> point = {point_in_world.x(), point_in_world.y(), point_in_world.z()};
  const Eigen::Vector3d point_in_camera = camera.rotation * point_in_world + camera.translation;
  double largest_length = 0.0, largest_angle = 0.0;  // mm: translation and point; rad: rotation
  for (int i = 0; i < 3; ++i) {
    largest_length = std::max({largest_length, std::abs(pose[3 + i]), std::abs(point[i])});
    largest_angle = std::max(largest_angle, std::abs(pose[i]));
  }
  const double first_step_mm = std::max(testing::RiddersFirstStep(largest_length),
                                        testing::RiddersFirstStep(largest_angle) * point_in_camera.norm());

  // The observation is off the projection, so that the residual is not zero.
  std::unique_ptr<ceres::CostFunction> cost(MarkerReprojectionError::Create(pixel + Eigen::Vector2d(7.0, -5.0)));
  const double* parameters[] = {pose.data(), intrinsics.data(), point.data()};
  EXPECT_TRUE(testing::GradientsMatchNumeric(*cost, nullptr, parameters, first_step_mm, point_in_camera.z(),
                                             "camera " + std::to_string(camera.id) + " pixel (" +
                                                 std::to_string(pixel.x()) + ", " + std::to_string(pixel.y()) +
                                                 ") at " + std::to_string(distance_mm) + " mm"));
}

// Every camera of two rigs (the walk's, and the fixed ring with other lenses), points near every
// image corner and two edges, near and far. Not the image centre: the lens terms' derivatives
// vanish there (r^2 to r^6 of a tiny r), and a relative comparison of 1e-9 px against numeric
// differences of 1e-11 px of roundoff says nothing about either.
TEST(MarkerReprojectionErrorTest, GradientMatchesNumeric) {
  const MarkerTrajectories motion = testing::WalkOrSyntheticWalker(MOCAP_SHARED_DIR);
  for (const Rig& rig : {WalkRig(motion), testing::RingRig(6, 4)}) {
    for (const Camera& camera : rig.cameras) {
      const double w = camera.intrinsics.width, h = camera.intrinsics.height;
      for (const Eigen::Vector2d& pixel :
           {Eigen::Vector2d(80.0, 60.0), Eigen::Vector2d(w - 80.0, 60.0), Eigen::Vector2d(80.0, h - 60.0),
            Eigen::Vector2d(w - 80.0, h - 60.0), Eigen::Vector2d(0.5 * w, 40.0), Eigen::Vector2d(40.0, 0.5 * h)}) {
        for (const double distance_mm : {1500.0, 3000.0, 6000.0}) ExpectGradientMatchesNumeric(camera, pixel, distance_mm);
      }
    }
  }
}

}  // namespace
}  // namespace mocap

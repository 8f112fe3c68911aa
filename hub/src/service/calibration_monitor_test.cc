// The live monitor on a simulated walk seen through the live reconstruction: a camera bumped at
// the start is reported bumped within 2 s and re-solved near its true pose, one that only rolled
// a little is reported drifting and re-solved alike; a rig that did not move stays "ok" with no
// solve.
#include "service/calibration_monitor.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "calib/bump_detector.h"
#include "recon/reconstructor.h"
#include "simcore/camera_bump.h"
#include "simcore/motion_volume.h"
#include "simcore/projector.h"
#include "simcore/ring_rig.h"
#include "simcore/synthetic_motion.h"
#include "simcore/test_scenes.h"

namespace mocap::service {
namespace {

struct MonitorRun {
  long first_moved_frame = -1;  // frames after the start until the watched camera had the awaited state
};

// Median distance (px) between the motion's markers seen through two poses of one camera: what
// the camera's residuals show of a move once the reconstruction's noise is taken away.
double MedianImageShift(const MarkerTrajectories& motion, const Camera& calibrated, const Camera& moved) {
  std::vector<double> shifts;
  for (const Eigen::Vector3d& point : motion.points) {
    Eigen::Vector2d before, after;
    if (MarkerTrajectories::IsGap(point) || !calibrated.ProjectToPixel(point, &before) ||
        !moved.ProjectToPixel(point, &after) || !calibrated.InImage(before))
      continue;
    shifts.push_back((after - before).norm());
  }
  if (shifts.empty()) return 0.0;
  std::nth_element(shifts.begin(), shifts.begin() + shifts.size() / 2, shifts.end());
  return shifts[shifts.size() / 2];
}

// Feeds the motion, seen by `truth`, through a reconstructor of `calibration` and the monitor;
// every check is awaited, so the run does not depend on the worker's speed. The run notes when
// camera `watched` first had state `awaited`.
MonitorRun Feed(const MarkerTrajectories& motion, const Rig& calibration, const Rig& truth, uint32_t watched,
                CameraPoseState awaited, CalibrationMonitor* monitor, double occlusion = 0.01) {
  ProjectOptions project;
  project.noise_px = 0.15;
  project.occlusion = occlusion;
  project.seed = 3;
  FaultyProjector projector(truth, motion.NumMarkers(), project);
  ReconstructorOptions recon;
  Reconstructor reconstructor(calibration, recon);
  std::vector<ReconstructedPoint> points;
  std::vector<int> seeing;
  MonitorRun run;
  for (size_t f = 0; f < motion.NumFrames(); ++f) {
    FrameSet set;
    set.frame_number = motion.frame_numbers[f];
    set.cameras = projector.Project(set.frame_number, 0, &motion.points[f * motion.NumMarkers()], &seeing);
    reconstructor.Process(set, {}, &points);
    monitor->Add(set, reconstructor);
    monitor->Finish();
    for (size_t c = 0; c < calibration.cameras.size(); ++c) {
      if (calibration.cameras[c].id == watched && monitor->state(c) == awaited && run.first_moved_frame < 0)
        run.first_moved_frame = static_cast<long>(f);
    }
  }
  return run;
}

Rig WalkRig(const MarkerTrajectories& motion) {
  RingRigOptions options;
  options.cameras = 8;
  return MakeRingRig(ComputeMotionVolume(motion), options);
}

constexpr size_t kMovedIndex = 4;  // camera 5

// Camera 5 of `truth` moved: the monitor gives it state `expected` within 2 s and solves it back
// onto its true pose; no other camera is ever anything but ok, nor solved.
void ExpectMoveReportedAndResolved(const MarkerTrajectories& motion, const Rig& calibration, const Rig& truth,
                                   CameraPoseState expected) {
  CalibrationMonitorOptions options;
  options.resolve_every_s = 0.5;  // solve again on every check, so the last solve has a full window
  CalibrationMonitor monitor(calibration, motion.rate_hz, options);
  const uint32_t moved_id = calibration.cameras[kMovedIndex].id;
  const MonitorRun run = Feed(motion, calibration, truth, moved_id, expected, &monitor);
  ASSERT_GE(run.first_moved_frame, 0);
  EXPECT_LT(run.first_moved_frame, static_cast<long>(2.0 * motion.rate_hz));
  for (size_t c = 0; c < calibration.cameras.size(); ++c) {
    if (c == kMovedIndex) continue;
    EXPECT_EQ(monitor.state(c), CameraPoseState::kOk) << "camera " << calibration.cameras[c].id;
    EXPECT_FALSE(monitor.solved_pose(c).has_value());
  }
  ASSERT_TRUE(monitor.solved_pose(kMovedIndex).has_value());
  const Camera& solved = *monitor.solved_pose(kMovedIndex);
  const Camera& moved = truth.cameras[kMovedIndex];
  const PoseChange error = ComparePoses(solved, moved);
  const double image_error_px = MedianImageShift(motion, moved, solved);
  std::printf("live: %s after %ld frames (%.2f s); last solve off the truth by %.3f mm, %.4f deg, %.3f px\n",
              CameraPoseStateName(expected), run.first_moved_frame + 1, (run.first_moved_frame + 1) / motion.rate_hz,
              error.centre_mm, error.rotation_deg, image_error_px);
  // The solved pose puts the markers where the true one does, to a fraction of the 0.15 px noise.
  EXPECT_LT(image_error_px, 0.05);
  // A camera that sees the subject in a narrow cone has one weakly determined direction: a shift
  // of its centre across the view with the turn that keeps the subject in place. A 2 s window
  // leaves an error of that pair, 0.13-0.86 mm with 0.002-0.013 deg alike on either walk (3
  // bumps, solves of 1.5 and 2 s windows), so the centre's bound is the rotation's at the
  // subject's distance: 0.02 deg, ~1.2 mm at 3.4 m (0.5 mm, the bound before, sits mid-spread).
  EXPECT_LT(error.rotation_deg, 0.02);
  const double distance_mm = (ComputeMotionVolume(motion).Center() - moved.CenterInWorld()).norm();
  EXPECT_LT(error.centre_mm, 0.02 * M_PI / 180.0 * distance_mm);
  const nlohmann::json status = monitor.StatusJson();
  EXPECT_EQ(status["cameras"][kMovedIndex]["state"], CameraPoseStateName(expected));
  EXPECT_EQ(status["cameras"][kMovedIndex]["solve"]["accepted"], true);
  EXPECT_GT(status["checks"].get<int>(), 0);
}

// A knock of 0.5 deg and 5 mm about an axis 44 deg off the optical axis (seed 1) moves camera
// 5's markers by about 5 px on either walk. The seed was 2 until the test ran on the synthetic
// walker: that axis is 10.6 deg off the optical axis, nearly a roll, which turns markers near
// the image centre by little, and the shift then hung on the world direction of the 5 mm: 2.2 px
// on the real walk (y up), 1.5 px on the synthetic one (z up), where the monitor rightly said
// drifting (the roll case has a test of its own below). So the shift, the monitor's own
// definition of bumped, is asserted well above bump_px first.
TEST(CalibrationMonitorTest, BumpedCameraIsReportedWithinTwoSecondsAndResolved) {
  const MarkerTrajectories motion = testing::WalkOrSyntheticWalker(MOCAP_SHARED_DIR);
  const Rig calibration = WalkRig(motion);
  Rig truth = calibration;
  ApplyCameraBump({5, 0.5, 5.0, 0.0, 1}, &truth);
  const double shift_px = MedianImageShift(motion, calibration.cameras[kMovedIndex], truth.cameras[kMovedIndex]);
  ASSERT_GT(shift_px, 2.0 * BumpDetectionOptions().bump_px);
  ExpectMoveReportedAndResolved(motion, calibration, truth, CameraPoseState::kBumped);
}

// A camera turned 0.5 deg about its own optical axis moves markers near the image centre by about
// 1 px: more than the rig's residuals, less than bump_px. It is reported drifting and solved
// back all the same.
TEST(CalibrationMonitorTest, RolledCameraIsReportedDriftingAndResolved) {
  const MarkerTrajectories motion = testing::WalkOrSyntheticWalker(MOCAP_SHARED_DIR);
  const Rig calibration = WalkRig(motion);
  Rig truth = calibration;
  Camera& rolled = truth.cameras[kMovedIndex];
  const Eigen::Vector3d centre = rolled.CenterInWorld();
  rolled.rotation = Eigen::AngleAxisd(0.5 * M_PI / 180.0, Eigen::Vector3d::UnitZ()).toRotationMatrix() * rolled.rotation;
  rolled.translation = -rolled.rotation * centre;
  const double shift_px = MedianImageShift(motion, calibration.cameras[kMovedIndex], rolled);
  ASSERT_GT(shift_px, 1.5 * BumpDetectionOptions().drift_px);
  ASSERT_LT(shift_px, BumpDetectionOptions().bump_px);
  ExpectMoveReportedAndResolved(motion, calibration, truth, CameraPoseState::kDrifting);
}

// The cases live: 10 cameras with lens distortion, a 10 s walk with 3 % occlusion, one
// camera knocked 0.5 deg / 5 mm, 2 deg / 20 mm and 5 deg / 50 mm (then its markers move by more
// than their spacing). The monitor, judging 10 s windows, finds it again from the subject within
// 0.3 mm and 0.02 deg and offers the pose (status JSON) for the API to apply.
TEST(CalibrationMonitorTest, KnockedCameraIsFoundAgainAndOffered) {
  SyntheticMotionOptions walk;
  walk.markers = 41;
  walk.rate_hz = 60.0;
  walk.frames = 600;
  walk.seed = 5;
  const MarkerTrajectories motion = MakeSyntheticMotion(walk);
  RingRigOptions ring;
  ring.cameras = 10;
  const Rig calibration = MakeRingRig(ComputeMotionVolume(motion), ring);
  struct Knock {
    double degrees, mm;
  };
  for (const Knock knock : {Knock{0.5, 5.0}, Knock{2.0, 20.0}, Knock{5.0, 50.0}}) {
    SCOPED_TRACE(std::to_string(knock.degrees) + " deg / " + std::to_string(knock.mm) + " mm");
    Rig truth = calibration;
    ApplyCameraBump({5, knock.degrees, knock.mm, 0.0, 4}, &truth);
    CalibrationMonitorOptions options;
    options.window_s = 10.0;
    options.check_every_s = 2.5;
    options.resolve_every_s = 0.0;
    options.frames_per_window = 600;
    CalibrationMonitor monitor(calibration, motion.rate_hz, options);
    const MonitorRun run = Feed(motion, calibration, truth, 5, CameraPoseState::kBumped, &monitor, 0.03);
    ASSERT_GE(run.first_moved_frame, 0);
    ASSERT_TRUE(monitor.solved_pose(kMovedIndex).has_value()) << monitor.StatusJson().dump();
    const PoseChange error = ComparePoses(*monitor.solved_pose(kMovedIndex), truth.cameras[kMovedIndex]);
    std::printf("live, %.1f deg / %.0f mm knock: bumped after %ld frames; last solve (of %.0f s) off the truth by "
                "%.3f mm, %.4f deg\n",
                knock.degrees, knock.mm, run.first_moved_frame + 1, options.window_s, error.centre_mm,
                error.rotation_deg);
    EXPECT_LT(error.centre_mm, 0.3);
    EXPECT_LT(error.rotation_deg, 0.02);
    for (size_t c = 0; c < calibration.cameras.size(); ++c) {
      if (c != kMovedIndex) {
        EXPECT_FALSE(monitor.solved_pose(c).has_value()) << "camera " << c + 1;
      }
    }
    // The offered move is the knock.
    const nlohmann::json solve = monitor.StatusJson()["cameras"][kMovedIndex]["solve"];
    EXPECT_TRUE(solve["accepted"].get<bool>());
    const PoseChange knocked = ComparePoses(truth.cameras[kMovedIndex], calibration.cameras[kMovedIndex]);
    EXPECT_NEAR(solve["centre_change_mm"].get<double>(), knocked.centre_mm, 0.3);
    EXPECT_NEAR(solve["rotation_change_deg"].get<double>(), knocked.rotation_deg, 0.02);
  }
}

TEST(CalibrationMonitorTest, UnmovedRigStaysOkWithoutSolves) {
  const MarkerTrajectories motion = testing::WalkOrSyntheticWalker(MOCAP_SHARED_DIR);
  const Rig calibration = WalkRig(motion);
  CalibrationMonitor monitor(calibration, motion.rate_hz, CalibrationMonitorOptions());
  Feed(motion, calibration, calibration, 0, CameraPoseState::kBumped, &monitor);
  for (size_t c = 0; c < calibration.cameras.size(); ++c) {
    EXPECT_EQ(monitor.state(c), CameraPoseState::kOk) << "camera " << calibration.cameras[c].id;
    EXPECT_FALSE(monitor.solved_pose(c).has_value());
  }
  EXPECT_FALSE(monitor.StatusJson()["cameras"][0].contains("solve"));
}

TEST(CalibrationMonitorTest, OptionsAreChecked) {
  const Rig rig;
  CalibrationMonitorOptions options;
  options.window_s = 0.0;
  EXPECT_THROW(CalibrationMonitor(rig, 60.0, options), std::invalid_argument);
  EXPECT_THROW(CalibrationMonitor(rig, 0.0, CalibrationMonitorOptions()), std::invalid_argument);
}

}  // namespace
}  // namespace mocap::service

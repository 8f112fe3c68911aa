// The live monitor on a simulated walk seen through the live reconstruction: a camera bumped at
// the start is reported bumped within 2 s and re-solved near its true pose; a rig that did not
// move stays "ok" with no solve.
#include "service/calibration_monitor.h"

#include <memory>
#include <string>

#include <gtest/gtest.h>

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
  long first_bumped_frame = -1;  // frames after the start
};

// Feeds the motion, seen by `truth`, through a reconstructor of `calibration` and the monitor;
// every check is awaited, so the run does not depend on the worker's speed.
MonitorRun Feed(const MarkerTrajectories& motion, const Rig& calibration, const Rig& truth, uint32_t watched,
         CalibrationMonitor* monitor) {
  ProjectOptions project;
  project.noise_px = 0.15;
  project.occlusion = 0.01;
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
      if (calibration.cameras[c].id == watched && monitor->state(c) == CameraPoseState::kBumped &&
          run.first_bumped_frame < 0)
        run.first_bumped_frame = static_cast<long>(f);
    }
  }
  return run;
}

Rig WalkRig(const MarkerTrajectories& motion) {
  RingRigOptions options;
  options.cameras = 8;
  return MakeRingRig(ComputeMotionVolume(motion), options);
}

TEST(CalibrationMonitorTest, BumpedCameraIsReportedWithinTwoSecondsAndResolved) {
  const MarkerTrajectories motion = testing::WalkOrSyntheticWalker(MOCAP_SHARED_DIR);
  const Rig calibration = WalkRig(motion);
  Rig truth = calibration;
  ApplyCameraBump({5, 0.5, 5.0, 0.0, 2}, &truth);
  CalibrationMonitorOptions options;
  options.resolve_every_s = 0.5;  // solve again on every check, so the last solve has a full window
  CalibrationMonitor monitor(calibration, motion.rate_hz, options);
  const MonitorRun run = Feed(motion, calibration, truth, 5, &monitor);
  ASSERT_GE(run.first_bumped_frame, 0);
  EXPECT_LT(run.first_bumped_frame, static_cast<long>(2.0 * motion.rate_hz));
  for (size_t c = 0; c < calibration.cameras.size(); ++c) {
    if (calibration.cameras[c].id == 5) continue;
    EXPECT_EQ(monitor.state(c), CameraPoseState::kOk) << "camera " << calibration.cameras[c].id;
    EXPECT_FALSE(monitor.solved_pose(c).has_value());
  }
  ASSERT_TRUE(monitor.solved_pose(4).has_value());
  const PoseChange error = ComparePoses(*monitor.solved_pose(4), truth.cameras[4]);
  std::printf("live: bumped after %ld frames (%.2f s); last solve off the truth by %.3f mm, %.4f deg\n",
              run.first_bumped_frame + 1, (run.first_bumped_frame + 1) / motion.rate_hz, error.centre_mm,
              error.rotation_deg);
  EXPECT_LT(error.centre_mm, 0.5);
  EXPECT_LT(error.rotation_deg, 0.02);
  const nlohmann::json status = monitor.StatusJson();
  EXPECT_EQ(status["cameras"][4]["state"], "bumped");
  EXPECT_EQ(status["cameras"][4]["solve"]["accepted"], true);
  EXPECT_GT(status["checks"].get<int>(), 0);
}

TEST(CalibrationMonitorTest, UnmovedRigStaysOkWithoutSolves) {
  const MarkerTrajectories motion = testing::WalkOrSyntheticWalker(MOCAP_SHARED_DIR);
  const Rig calibration = WalkRig(motion);
  CalibrationMonitor monitor(calibration, motion.rate_hz, CalibrationMonitorOptions());
  Feed(motion, calibration, calibration, 0, &monitor);
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

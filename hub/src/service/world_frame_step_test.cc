// The floor / L-frame step without a loop or a socket: an 8-camera ring sees the default L-frame
// lying still at the truth world's origin, but serve's calibration (as a wand leaves it) has its
// world turned 5 deg off the vertical and shifted. The step finds the 4 markers, removes the tilt
// (the solved cameras land on the truth) and reports it; with a marker hidden, or other markers
// crowding it, it is refused with what it saw; floor markers level the world alike.
#include "service/world_frame_step.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "calib/world_frame.h"
#include "service/api_error.h"
#include "simcore/motion_volume.h"
#include "simcore/projector.h"
#include "simcore/ring_rig.h"
#include "simcore/synthetic_motion.h"

namespace mocap::service {
namespace {

constexpr double kTiltDeg = 5.0;

Rig TruthRig() {
  SyntheticMotionOptions options;
  options.markers = 20;
  options.frames = 60;
  options.seed = 2;
  RingRigOptions ring;
  ring.cameras = 8;
  ring.lens_distortion = true;
  return MakeRingRig(ComputeMotionVolume(MakeSyntheticMotion(options)), ring);
}

// Serve's calibration: the same cameras in a world turned kTiltDeg about x and shifted.
SimilarityTransform WandWorldFromTruth() {
  SimilarityTransform t;
  t.rotation = Eigen::AngleAxisd(kTiltDeg * M_PI / 180.0, Eigen::Vector3d::UnitX()).toRotationMatrix() *
               Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  t.translation = Eigen::Vector3d(400.0, -250.0, 1200.0);
  return t;
}

// `frames` frame sets of `markers` (truth world) lying still, as the truth rig sees them.
std::vector<FrameSet> StillMarkers(const Rig& truth, const std::vector<Eigen::Vector3d>& markers, int frames) {
  ProjectOptions project;
  project.noise_px = 0.15;
  project.seed = 3;
  FaultyProjector projector(truth, markers.size(), project);
  std::vector<FrameSet> sets;
  std::vector<int> seeing;
  for (int f = 0; f < frames; ++f) {
    FrameSet set;
    set.frame_number = static_cast<uint64_t>(f);
    set.cameras = projector.Project(set.frame_number, 0, markers.data(), &seeing);
    sets.push_back(set);
  }
  return sets;
}

double CentreError(const Rig& a, const Rig& b) {
  double worst = 0.0;
  for (size_t c = 0; c < a.cameras.size(); ++c)
    worst = std::max(worst, (a.cameras[c].CenterInWorld() - b.cameras[c].CenterInWorld()).norm());
  return worst;
}

TEST(WorldFrameStep, TheLFrameRemovesTheWandsTilt) {
  const Rig truth = TruthRig();
  const Rig served = TransformRig(truth, WandWorldFromTruth());
  const std::vector<FrameSet> frames = StillMarkers(truth, DefaultLFrame(2), 60);
  const WorldFrameSolution s = SolveWorldFrame(frames, served, WorldFrameRequest());
  std::printf("L-frame: %s\n", s.report.dump().c_str());
  EXPECT_EQ(s.report["method"], "lframe");
  EXPECT_EQ(s.report["frames_used"], 60);
  EXPECT_EQ(s.report["points_per_frame"], 4);
  ASSERT_EQ(s.report["markers"].size(), 4u);
  for (const auto& m : s.report["markers"]) EXPECT_LT(m["error_mm"].get<double>(), 1.0) << m;
  EXPECT_LT(s.report["fit_rms_mm"].get<double>(), 0.5);
  EXPECT_NEAR(s.report["tilt_removed_deg"].get<double>(), kTiltDeg, 0.05);
  EXPECT_LT(CentreError(s.rig, truth), 1.0);
  EXPECT_GT(CentreError(served, truth), 100.0);  // what the step had to undo
}

TEST(WorldFrameStep, AHiddenMarkerIsRefusedWithWhatWasSeen) {
  const Rig truth = TruthRig();
  const Rig served = TransformRig(truth, WandWorldFromTruth());
  std::vector<Eigen::Vector3d> three = DefaultLFrame(2);
  three.pop_back();
  try {
    SolveWorldFrame(StillMarkers(truth, three, 30), served, WorldFrameRequest());
    FAIL() << "a 3-marker scene passed for a 4-marker L-frame";
  } catch (const ApiError& e) {
    EXPECT_EQ(e.status, 422);
    EXPECT_NE(std::string(e.what()).find("was found in 0 frames"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("3 of its 4 markers reconstructed"), std::string::npos) << e.what();
  }
}

TEST(WorldFrameStep, OtherMarkersInViewAreNamedWhenTheLFrameIsNotFound) {
  const Rig truth = TruthRig();
  const Rig served = TransformRig(truth, WandWorldFromTruth());
  // An L-frame of other dimensions (arms 250 / 450 mm) and two stray markers.
  const std::vector<Eigen::Vector3d> scene = {{0, 0, 0}, {250, 0, 0}, {450, 0, 0}, {0, 300, 0}, {-300, -300, 0},
                                              {300, 400, 0}};
  try {
    SolveWorldFrame(StillMarkers(truth, scene, 30), served, WorldFrameRequest());
    FAIL() << "another geometry passed for the default L-frame";
  } catch (const ApiError& e) {
    EXPECT_EQ(e.status, 422);
    EXPECT_NE(std::string(e.what()).find("6 points reconstructed per frame set (median), more than its 4 markers"),
              std::string::npos)
        << e.what();
  }
}

TEST(WorldFrameStep, FloorMarkersLevelTheWorld) {
  const Rig truth = TruthRig();
  const Rig served = TransformRig(truth, WandWorldFromTruth());
  const std::vector<Eigen::Vector3d> floor = {{-300, -200, 0}, {350, -150, 0}, {0, 400, 0}, {200, 250, 0}};
  WorldFrameRequest request;
  request.method = kWorldMethodFloor;
  const WorldFrameSolution s = SolveWorldFrame(StillMarkers(truth, floor, 30), served, request);
  EXPECT_EQ(s.report["method"], "floor");
  EXPECT_NEAR(s.report["tilt_removed_deg"].get<double>(), kTiltDeg, 0.05);
  // Levelled: every camera's height above the floor is the truth's (the heading and the origin
  // within the floor are the floor step's own).
  for (size_t c = 0; c < truth.cameras.size(); ++c)
    EXPECT_NEAR(s.rig.cameras[c].CenterInWorld().z(), truth.cameras[c].CenterInWorld().z(), 1.0) << c;
}

TEST(WorldFrameStep, RequestsAreChecked) {
  WorldFrameRequest r;
  r.method = "wall";
  EXPECT_THROW(r.Check(), ApiError);
  r = WorldFrameRequest();
  r.frames = 5;
  EXPECT_THROW(r.Check(), ApiError);
  r = WorldFrameRequest();
  r.lframe = {{0, 0, 0}, {1, 0, 0}};
  EXPECT_THROW(r.Check(), ApiError);
  r = WorldFrameRequest();
  r.lframe = {{0, 0, 0}, {100, 0, 0}, {200, 0, 0}};  // collinear: refused by the solve as a bad model
  try {
    SolveWorldFrame({}, TruthRig(), r);
    FAIL();
  } catch (const ApiError& e) {
    EXPECT_EQ(e.status, 400);
  }
}

}  // namespace
}  // namespace mocap::service

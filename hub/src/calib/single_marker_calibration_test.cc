// Single-marker wanding on simulated rings of 8 and 12 cameras with lens distortion: one marker
// waved (0.15 px noise, 1 % occlusion), then the wand shown as the scale bar; after a rigid fit
// the centres lie within 1 mm of the truth, the rotations within 0.05 deg and the scale within
// 0.1 %. Too few frames, and no scale bar, are refused with what to do.
#include "calib/single_marker_calibration.h"

#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "geometry/rigid_fit.h"
#include "simcore/motion_volume.h"
#include "simcore/projector.h"
#include "simcore/ring_rig.h"
#include "simcore/synthetic_motion.h"
#include "simcore/wand.h"

namespace mocap {
namespace {

Rig Ring(int cameras) {
  SyntheticMotionOptions walk;
  walk.markers = 30;
  walk.frames = 60;
  RingRigOptions ring;
  ring.cameras = cameras;
  return MakeRingRig(ComputeMotionVolume(MakeSyntheticMotion(walk)), ring);
}

// `waved` frames of a single marker, then `bar` frames of a 500 mm wand, as `truth` sees them.
std::vector<FrameSet> Wave(const Rig& truth, int waved, int bar, uint64_t seed) {
  WandMotionOptions wave;
  wave.wand_length_mm = 500.0;
  wave.frames = waved + bar;
  wave.single_marker_frames = waved;
  wave.seed = seed;
  const MarkerTrajectories motion = MakeWandMotion(truth, wave);
  ProjectOptions project;
  project.noise_px = 0.15;
  project.occlusion = 0.01;
  project.seed = seed;
  FaultyProjector projector(truth, motion.NumMarkers(), project);
  std::vector<FrameSet> frames;
  std::vector<int> seeing;
  for (size_t f = 0; f < motion.NumFrames(); ++f) {
    FrameSet set;
    set.frame_number = motion.frame_numbers[f];
    set.cameras = projector.Project(set.frame_number, 0, &motion.points[f * motion.NumMarkers()], &seeing);
    frames.push_back(std::move(set));
  }
  return frames;
}

struct Errors {
  double centre_mm = 0.0;
  double rotation_deg = 0.0;
  double scale = 1.0;
};

Errors Compare(const Rig& truth, const Rig& result) {
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
    errors.centre_mm = std::max(errors.centre_mm, (rigid.Apply(camera.CenterInWorld()) - expected.CenterInWorld()).norm());
    const Eigen::Matrix3d aligned = camera.rotation * rigid.rotation.transpose();
    errors.rotation_deg =
        std::max(errors.rotation_deg, Eigen::AngleAxisd(aligned * expected.rotation.transpose()).angle() * 180.0 / M_PI);
  }
  return errors;
}

class SingleMarkerRigTest : public ::testing::TestWithParam<int> {};

TEST_P(SingleMarkerRigTest, MeetsTheAccuracyTargets) {
  const Rig truth = Ring(GetParam());
  const std::vector<FrameSet> frames = Wave(truth, 3000, 300, 7);
  SingleMarkerOptions options;
  options.scale_length_mm = 500.0;
  const SingleMarkerResult result = CalibrateSingleMarker(frames, truth, options);
  ASSERT_EQ(result.rig.cameras.size(), truth.cameras.size());
  const Errors errors = Compare(truth, result.rig);
  double worst_rms = 0.0;
  for (const SingleMarkerCamera& c : result.cameras) worst_rms = std::max(worst_rms, c.rms_px);
  std::printf("%d cameras: %zu frames used of %zu, %zu scale frames (length RMS %.3f mm); max centre error %.3f mm, "
              "rotation %.4f deg, scale %+.4f %%; worst camera rms %.3f px\n",
              GetParam(), result.frames_used, result.frames_selected, result.scale_frames,
              result.scale_length_rms_mm, errors.centre_mm, errors.rotation_deg, 100.0 * (errors.scale - 1.0),
              worst_rms);
  EXPECT_LT(errors.centre_mm, 1.0);
  EXPECT_LT(errors.rotation_deg, 0.05);
  EXPECT_LT(std::abs(errors.scale - 1.0), 0.001);
  // Every bar frame's ends paired right: one swapped view puts that frame's length tens of mm off.
  EXPECT_LT(result.scale_length_rms_mm, 2.0);
  for (const SingleMarkerCamera& c : result.cameras) {
    EXPECT_GT(c.used, 300u) << c.id;
    EXPECT_LT(c.rms_px, 1.3 * std::sqrt(2.0) * 0.15) << c.id;  // noise level: the model fits
  }
}

INSTANTIATE_TEST_SUITE_P(Rings, SingleMarkerRigTest, ::testing::Values(8, 12));

TEST(SingleMarkerCalibrationTest, RefusesWithWhatToDo) {
  const Rig truth = Ring(6);
  SingleMarkerOptions options;
  options.scale_length_mm = 500.0;
  try {
    CalibrateSingleMarker(Wave(truth, 1500, 0, 3), truth, options);
    FAIL() << "no scale bar was shown";
  } catch (const std::runtime_error& error) {
    EXPECT_NE(std::string(error.what()).find("scale bar"), std::string::npos) << error.what();
  }
  try {
    CalibrateSingleMarker(Wave(truth, 10, 0, 3), truth, options);
    FAIL() << "ten frames cannot calibrate";
  } catch (const std::runtime_error& error) {
    EXPECT_NE(std::string(error.what()).find("wave one marker"), std::string::npos) << error.what();
  }
  options.scale_length_mm = 0.0;
  EXPECT_THROW(options.Check(), std::invalid_argument);
}

}  // namespace
}  // namespace mocap

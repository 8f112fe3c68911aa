// The rig's centroid noise: its scale, the calibration's value, the gates it sets, and the
// reconstruction measuring it from its own residuals on a precise and on a webcam-like rig.
#include "recon/rig_noise.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "recon/reconstructor.h"
#include "simcore/test_scenes.h"

namespace mocap {
namespace {

TEST(RigNoise, MillimetresPerPixelAtTheVolumeTheAxesMeetIn) {
  const Eigen::Vector3d target(0, 0, 1000);
  const Rig rig = testing::MakeRingRig(8, 4000.0, 2200.0, target, 1100.0);
  std::vector<double> scales;
  for (const Camera& camera : rig.cameras) scales.push_back((camera.CenterInWorld() - target).norm() / 1100.0);
  std::sort(scales.begin(), scales.end());
  EXPECT_NEAR(RigMmPerPx(rig), scales[scales.size() / 2], 1e-6);
}

TEST(RigNoise, CalibratedNoiseIsTheKnownCamerasRmsPerAxis) {
  Rig rig = testing::MakeRingRig(4, 4000.0, 2200.0, Eigen::Vector3d(0, 0, 1000));
  EXPECT_EQ(CalibratedNoisePx(rig), 0.0);
  rig.cameras[0].centroid_rms_px = 1.0;
  rig.cameras[2].centroid_rms_px = 2.0;  // cameras 1 and 3 unknown: not counted
  EXPECT_NEAR(CalibratedNoisePx(rig), std::sqrt((1.0 + 4.0) / 2.0 / 2.0), 1e-12);
}

TEST(RigNoise, GatesWidenWithTheNoiseAndNeverNarrow) {
  const ReconstructorOptions configured;
  const ReconstructorOptions precise = GatesForNoise(configured, 0.1, 4.0);
  EXPECT_EQ(precise.triangulation.max_reprojection_px, configured.triangulation.max_reprojection_px);
  EXPECT_EQ(precise.triangulation.max_merged_px, configured.triangulation.max_merged_px);
  EXPECT_EQ(precise.graph.max_ray_distance_mm, configured.graph.max_ray_distance_mm);
  EXPECT_EQ(precise.prediction.min_gate_px, configured.prediction.min_gate_px);

  const ReconstructorOptions webcam = GatesForNoise(configured, 2.0, 5.0);
  EXPECT_DOUBLE_EQ(webcam.triangulation.max_reprojection_px, 8.0);
  EXPECT_DOUBLE_EQ(webcam.triangulation.max_merged_px, 8.0);  // follows the reprojection limit
  EXPECT_DOUBLE_EQ(webcam.graph.max_ray_distance_mm, 50.0);
  EXPECT_DOUBLE_EQ(webcam.clustering.max_ray_distance_mm, 50.0);
  EXPECT_DOUBLE_EQ(webcam.prediction.min_gate_px, 8.0);
  EXPECT_NO_THROW(webcam.Check());
}

TEST(RigNoise, MergedLimitIsNeverBelowTheReprojectionLimit) {
  // The old trap: --max-reprojection-px above 4 was refused ("max_merged_px must be >= ...").
  TriangulationOptions options;
  options.max_reprojection_px = 6.0;
  EXPECT_NO_THROW(options.Check());
  EXPECT_EQ(options.MergedLimitPx(), 6.0);
}

// Reconstructs 60 frames of 30 markers on an 8-camera ring at the given noise; returns the
// reconstructor as it stands after them.
struct NoiseRun {
  double measured_px = 0.0;
  ReconstructorOptions gates;
  double found = 0.0;  // share of the last 20 frames' markers found within 5 sigmas' error
};

NoiseRun RunAtNoise(double noise_px, double prior_px) {
  Rig rig = testing::MakeRingRig(8, 4000.0, 2200.0, Eigen::Vector3d(0, 0, 1000));
  for (Camera& camera : rig.cameras) camera.centroid_rms_px = prior_px * std::sqrt(2.0);
  testing::SyntheticMotion motion(30, 3, 41);
  testing::ProjectionFaults faults;
  faults.noise_px = noise_px;
  testing::FrameProjector projector(rig, faults, 42);
  Reconstructor reconstructor(rig, ReconstructorOptions());
  const double point_tolerance_mm = 5.0 * noise_px * RigMmPerPx(rig) + 1.0;
  FrameSet frame_set;
  testing::BlobTruth truth;
  std::vector<ReconstructedPoint> points;
  NoiseRun run;
  int found = 0, markers = 0;
  for (int f = 0; f < 60; ++f) {
    const std::vector<Eigen::Vector3d> truth_points = motion.At(f / 100.0);
    projector.Project(f, truth_points, &frame_set, &truth);
    reconstructor.Process(frame_set, {}, &points);
    if (f < 40) continue;
    for (const Eigen::Vector3d& marker : truth_points) {
      ++markers;
      for (const ReconstructedPoint& point : points) {
        if ((point.point_in_world - marker).norm() < point_tolerance_mm) {
          ++found;
          break;
        }
      }
    }
  }
  run.measured_px = reconstructor.centroid_noise_px();
  run.gates = reconstructor.gates();
  run.found = static_cast<double>(found) / markers;
  return run;
}

TEST(RigNoise, PreciseRigKeepsTheConfiguredGates) {
  const NoiseRun run = RunAtNoise(0.2, 0.0);
  EXPECT_NEAR(run.measured_px, 0.2, 0.04);
  const ReconstructorOptions configured;
  EXPECT_EQ(run.gates.triangulation.max_reprojection_px, configured.triangulation.max_reprojection_px);
  EXPECT_EQ(run.gates.graph.max_ray_distance_mm, configured.graph.max_ray_distance_mm);
  EXPECT_GT(run.found, 0.99);
}

TEST(RigNoise, WebcamNoiseIsMeasuredAndTheGatesOpenWithoutOptions) {
  // No calibration value: the gates start at the configured ones (tuned for 0.2 px) and open as
  // the residuals show the noise. The 1.5 px limit alone keeps few of these points.
  const NoiseRun run = RunAtNoise(2.0, 0.0);
  EXPECT_NEAR(run.measured_px, 2.0, 0.3);
  EXPECT_NEAR(run.gates.triangulation.max_reprojection_px, 4.0 * run.measured_px, 1e-9);
  EXPECT_GT(run.found, 0.98);
}

TEST(RigNoise, CalibratedNoiseSetsTheGatesFromTheFirstFrame) {
  const NoiseRun run = RunAtNoise(2.0, 2.0);
  EXPECT_NEAR(run.measured_px, 2.0, 0.3);
  EXPECT_GT(run.found, 0.98);
}

TEST(CentroidNoiseMeter, LowerQuartileOverPointsOfTheirDegreesOfFreedom) {
  CentroidNoiseMeter meter(0.5);
  EXPECT_EQ(meter.sigma_px(), 0.5);  // the prior until a frame is measured
  std::vector<TriangulatedPoint> points(2);
  for (TriangulatedPoint& point : points) {
    point.observations = {0, 1, 2, 3};
    point.rms_px = 1.0;
  }
  meter.AddFrame(points);  // too few points to say anything
  EXPECT_EQ(meter.frames_measured(), 0);
  points.resize(9, points[0]);
  // Four views: 8 residuals, 5 degrees of freedom; the sum of squares is 4 px^2.
  meter.AddFrame(points);
  const double v = 2.0 / 45.0;
  const double t = 1.0 - v - 0.6745 * std::sqrt(v);
  EXPECT_NEAR(meter.sigma_px(), std::sqrt(4.0 / 5.0 / (t * t * t)), 1e-12);
}

}  // namespace
}  // namespace mocap

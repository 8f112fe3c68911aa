// Two cameras only (seed 000's rig): markers seen by two views are reconstructed and tracked,
// the ambiguity of two rays resolved over time; and the same pipeline told to need three views
// finds nothing, as it did before two-view points existed.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <vector>

#include <gtest/gtest.h>

#include "recon/reconstructor.h"
#include "recon/rig_noise.h"
#include "simcore/test_scenes.h"
#include "track/tracker.h"

namespace mocap {
namespace {

struct TwoViewRun {
  double found = 0.0;            // share of the markers both cameras see, matched within the gate
  double ghosts_per_frame = 0.0;  // measured output samples beyond the gate of every marker
  int markers_output = 0;
};

TwoViewRun RunTwoCameras(double noise_px, int min_views) {
  // Two cameras 90 degrees apart around the volume, 4 m away.
  Rig rig;
  rig.cameras.push_back(testing::LookAtCamera(1, Eigen::Vector3d(4000, 0, 2000), Eigen::Vector3d(0, 0, 900)));
  rig.cameras.push_back(testing::LookAtCamera(2, Eigen::Vector3d(0, 4000, 1800), Eigen::Vector3d(0, 0, 900)));
  testing::SyntheticMotion motion(12, 3, 51);
  testing::ProjectionFaults faults;
  faults.noise_px = noise_px;
  testing::FrameProjector projector(rig, faults, 52);
  ReconstructorOptions recon;
  recon.min_views_without_prediction = min_views;
  Reconstructor reconstructor(rig, recon);
  TrackerOptions tracker_options;
  tracker_options.rate_hz = 100.0;
  tracker_options.birth_min_views = min_views;
  Tracker tracker(tracker_options);
  FrameSet frame_set;
  testing::BlobTruth blob_truth;
  std::vector<ReconstructedPoint> points;
  std::vector<TrackSample> samples;
  std::map<uint64_t, std::vector<TrackSample>> rows;
  std::vector<std::vector<Eigen::Vector3d>> seen_by_both;
  const int frames = 200;
  for (int f = 0; f < frames; ++f) {
    const std::vector<Eigen::Vector3d> markers = motion.At(f / 100.0);
    projector.Project(f, markers, &frame_set, &blob_truth);
    std::vector<int> views(markers.size(), 0);
    for (const std::vector<int>& camera : blob_truth) {
      for (int m : camera) {
        if (m >= 0) ++views[m];
      }
    }
    seen_by_both.emplace_back();
    for (size_t m = 0; m < markers.size(); ++m) {
      if (views[m] == 2) seen_by_both.back().push_back(markers[m]);
    }
    reconstructor.Process(frame_set, tracker.Predict(f), &points);
    tracker.FollowPointNoise(reconstructor.point_noise_mm());
    samples.clear();
    tracker.Update(f, points, &samples);
    for (const TrackSample& sample : samples) rows[sample.frame_number].push_back(sample);
  }
  TwoViewRun run;
  run.markers_output = tracker.NumMarkers();
  // A two-view point's error at this noise: about noise_px times the rig's mm per px per axis.
  const double gate_mm = std::max(15.0, 6.0 * noise_px * RigMmPerPx(rig));
  // Scored after the first second: the tracks' births are behind.
  int found = 0, total = 0, ghosts = 0;
  for (int f = 100; f < frames; ++f) {
    const std::vector<TrackSample>& row = rows[f];
    for (const Eigen::Vector3d& marker : seen_by_both[f]) {
      ++total;
      for (const TrackSample& sample : row) {
        if ((sample.position - marker).norm() < gate_mm) {
          ++found;
          break;
        }
      }
    }
    for (const TrackSample& sample : row) {
      bool near = false;
      for (const Eigen::Vector3d& marker : seen_by_both[f]) near = near || (sample.position - marker).norm() < gate_mm;
      ghosts += !near && sample.kind == SampleKind::kMeasured;
    }
  }
  run.found = total > 0 ? static_cast<double>(found) / total : 0.0;
  run.ghosts_per_frame = static_cast<double>(ghosts) / (frames - 100);
  std::printf("two cameras, %.1f px, --min-views %d: %.2f %% found, %.3f ghosts/frame, %d trajectories for %zu markers\n",
              noise_px, min_views, 100.0 * run.found, run.ghosts_per_frame, run.markers_output,
              motion.At(0.0).size());
  return run;
}

TEST(TwoViews, TwoCamerasReconstructAndTrackEveryMarkerTheyBothSee) {
  const TwoViewRun run = RunTwoCameras(0.5, 2);
  EXPECT_GT(run.found, 0.97);
  EXPECT_LT(run.ghosts_per_frame, 0.05);
  EXPECT_LE(run.markers_output, 15);  // 12 markers: few broken or ghost trajectories
}

TEST(TwoViews, WebcamNoiseOnTwoCameras) {
  const TwoViewRun run = RunTwoCameras(2.0, 2);
  EXPECT_GT(run.found, 0.9);
  EXPECT_LT(run.ghosts_per_frame, 0.1);
}

TEST(TwoViews, ThreeViewsNeededFindNothingOnTwoCameras) {
  const TwoViewRun run = RunTwoCameras(0.5, 3);
  EXPECT_EQ(run.markers_output, 0);
}

}  // namespace
}  // namespace mocap

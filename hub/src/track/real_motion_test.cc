// Real recorded motions (../shared/data/motions; skipped, saying so, where that folder is missing)
// through a self-made 8-camera ring with the issue's faults, reconstructed and tracked: the
// done-when thresholds on every motion. The simulator's own rig and projector are checked by
// the CLI figures; this test keeps the recon/track layers honest on real movement by themselves.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <string>

#include <gtest/gtest.h>

#include "io/marker_trajectories.h"
#include "io/trc.h"
#include "recon/reconstructor.h"
#include "simcore/test_scenes.h"
#include "track/gap_filler.h"
#include "track/track_eval_testing.h"
#include "track/tracker.h"

namespace mocap {
namespace {

class RealMotion : public ::testing::TestWithParam<std::string> {};

TEST_P(RealMotion, MeetsTheIssueThresholds) {
  const MarkerTrajectories motion = ReadTrc(GetParam());
  const int up = DetectUpAxis(motion);
  ASSERT_GE(up, 0);
  // Permute axes so that up is z, the convention of the synthetic ring rig.
  const auto z_up = [up](const Eigen::Vector3d& p) {
    return Eigen::Vector3d(p[(up + 1) % 3], p[(up + 2) % 3], p[up]);
  };
  Eigen::Vector3d low = Eigen::Vector3d::Constant(1e18), high = -low;
  for (size_t f = 0; f < motion.NumFrames(); ++f) {
    for (size_t m = 0; m < motion.NumMarkers(); ++m) {
      if (!motion.Has(f, m)) continue;
      low = low.cwiseMin(z_up(motion.At(f, m)));
      high = high.cwiseMax(z_up(motion.At(f, m)));
    }
  }
  const Eigen::Vector3d centre = 0.5 * (low + high);
  const double half_width = 0.5 * std::max(high.x() - low.x(), high.y() - low.y());
  const Rig rig = testing::MakeRingRig(8, half_width + 3500.0, high.z() + 600.0, centre, 900.0);
  testing::ProjectionFaults faults;
  faults.noise_px = 0.2;
  faults.occlusion = 0.05;
  faults.occlusion_frames = 5;
  faults.spurious = 2;
  faults.drop_frames = 0.002;
  testing::FrameProjector projector(rig, faults, 7);

  Reconstructor reconstructor(rig, ReconstructorOptions());
  TrackerOptions tracker_options;
  tracker_options.rate_hz = motion.rate_hz;
  Tracker tracker(tracker_options);
  std::map<uint64_t, std::vector<TrackSample>> rows;
  GapFillOptions gap_fill;
  gap_fill.max_spline_gap = std::max(1, static_cast<int>(std::lround(0.05 * motion.rate_hz)));
  gap_fill.window_frames = std::max(gap_fill.max_spline_gap + 2, static_cast<int>(0.25 * motion.rate_hz));
  GapFiller filler(gap_fill, [&](uint64_t frame, const std::vector<TrackSample>& row) { rows[frame] = row; });

  std::vector<std::vector<Eigen::Vector3d>> truth(motion.NumFrames());
  std::vector<std::vector<int>> views_of(motion.NumFrames());
  FrameSet frame_set;
  testing::BlobTruth blob_truth;
  std::vector<ReconstructedPoint> points;
  std::vector<TrackSample> samples;
  for (size_t f = 0; f < motion.NumFrames(); ++f) {
    for (size_t m = 0; m < motion.NumMarkers(); ++m) {
      truth[f].push_back(motion.Has(f, m) ? z_up(motion.At(f, m)) : MarkerTrajectories::Gap());
    }
    projector.Project(f, truth[f], &frame_set, &blob_truth);
    views_of[f].assign(motion.NumMarkers(), 0);
    for (const auto& camera : blob_truth) {
      for (int m : camera) {
        if (m >= 0) ++views_of[f][m];
      }
    }
    reconstructor.Process(frame_set, tracker.Predict(f), &points);
    samples.clear();
    tracker.Update(f, points, &samples);
    filler.Add(f, samples);
  }
  samples.clear();
  tracker.Finish(&samples);
  filler.Add(motion.NumFrames() - 1, samples);
  filler.Finish();

  // Scored by eval's matching; a marker seen by fewer than two cameras is not missing.
  const MarkerEvalReport report = testing::EvaluateTrackRows(rows, truth, motion.rate_hz, 0, views_of);
  const double frames = static_cast<double>(motion.NumFrames());
  size_t truth_markers = 0;
  for (size_t m = 0; m < motion.NumMarkers(); ++m) {
    for (size_t f = 0; f < motion.NumFrames(); ++f) {
      if (motion.Has(f, m)) {
        ++truth_markers;
        break;
      }
    }
  }
  // One set of limits for every motion. rmse and ghosts: issue 4's reconstruction limits. Missing:
  // issue 5's end-to-end limit (0.01 per frame), because this test injects the end-to-end faults
  // (noise, occlusion, spurious blobs, dropped frames); issue 4's 0.005 holds for the walk and
  // the run but not for the serve (50 Hz, ~200 mm per frame at the racket hand), which measures
  // 0.008 through this rig (and 0.009 ghosts, close to its limit).
  EXPECT_LT(report.rmse_mm, 1.0);
  EXPECT_LE(report.ghosts / frames, 0.01);
  EXPECT_LE(report.missing / frames, 0.01);
  std::printf("%s: rmse %.3f mm, ghosts %.4f and missing %.4f per frame, %zu swaps, %d tracks for %zu markers\n",
              std::filesystem::path(GetParam()).stem().c_str(), report.rmse_mm, report.ghosts / frames,
              report.missing / frames, report.swaps, tracker.NumMarkers(), truth_markers);
  RecordProperty("rmse_mm", std::to_string(report.rmse_mm));
  RecordProperty("ghosts_per_frame", std::to_string(report.ghosts / frames));
  RecordProperty("missing_per_frame", std::to_string(report.missing / frames));
  EXPECT_LE(tracker.NumMarkers(), 1.2 * truth_markers);
}

// Empty where the shared data is missing (then the test below reports the skip).
std::vector<std::string> Motions() {
  std::vector<std::string> paths;
  if (!std::filesystem::is_directory(MOCAP_MOTIONS_DIR)) return paths;
  for (const auto& entry : std::filesystem::directory_iterator(MOCAP_MOTIONS_DIR)) {
    if (entry.path().extension() == ".trc") paths.push_back(entry.path().string());
  }
  std::sort(paths.begin(), paths.end());
  return paths;
}

TEST(RealMotions, SharedDataHoldsMotions) {
  if (!std::filesystem::is_directory(MOCAP_MOTIONS_DIR)) {
    GTEST_SKIP() << "../shared/data missing: no " << MOCAP_MOTIONS_DIR;
  }
  EXPECT_FALSE(Motions().empty()) << MOCAP_MOTIONS_DIR << " holds no .trc";
}

GTEST_ALLOW_UNINSTANTIATED_PARAMETERIZED_TEST(RealMotion);
INSTANTIATE_TEST_SUITE_P(SharedData, RealMotion, ::testing::ValuesIn(Motions()),
                         [](const auto& info) {
                           return std::filesystem::path(info.param).stem().string();
                         });

}  // namespace
}  // namespace mocap

// Reconstruction + tracking + gap filling on self-made motions: accuracy, no ghosts, few
// trajectories, ids that survive a full occlusion; plus the rigid-model stand-in.
#include "track/tracker.h"

#include <functional>
#include <map>

#include <gtest/gtest.h>

#include "recon/reconstructor.h"
#include "simcore/expected_failure.h"
#include "simcore/test_scenes.h"
#include "track/gap_filler.h"
#include "track/track_eval_testing.h"

namespace mocap {
namespace {

struct RunResult {
  std::map<uint64_t, std::vector<TrackSample>> rows;
  std::vector<std::vector<Eigen::Vector3d>> truth;
  // Per frame and truth marker, the live id of the point published within 5 mm of it (0: none).
  std::vector<std::vector<uint64_t>> live_ids;
  int live_ghosts = 0;  // points published farther than 5 mm from every truth marker
  int markers_output = 0;
  double rate_hz = 0.0;
};

// hide(frame, marker) removes a marker's blobs from every camera; frames where skip(frame) holds
// are never assembled (no frame set reaches the tracker).
RunResult RunPipeline(int frames, double rate_hz, const testing::ProjectionFaults& faults,
              const std::function<bool(int, int)>& hide, TrackerOptions tracker_options = {},
              const std::function<bool(int)>& skip = nullptr, int cameras = 8) {
  const Rig rig = testing::MakeRingRig(cameras, 4000.0, 2200.0, Eigen::Vector3d(0, 0, 1000));
  testing::SyntheticMotion motion(24, 4, 41);
  testing::FrameProjector projector(rig, faults, 42);
  Reconstructor reconstructor(rig, ReconstructorOptions());
  tracker_options.rate_hz = rate_hz;
  Tracker tracker(tracker_options);
  RunResult result;
  result.rate_hz = rate_hz;
  GapFiller filler(GapFillOptions(), [&](uint64_t frame, const std::vector<TrackSample>& row) {
    result.rows[frame] = row;
  });
  FrameSet frame_set;
  testing::BlobTruth blob_truth;
  std::vector<ReconstructedPoint> points;
  std::vector<TrackSample> samples;
  for (int f = 0; f < frames; ++f) {
    const auto markers = motion.At(f / rate_hz);
    result.truth.push_back(markers);
    result.live_ids.emplace_back(markers.size(), 0);
    if (skip && skip(f)) continue;
    projector.Project(f, markers, &frame_set, &blob_truth);
    for (CameraFrame& camera : frame_set.cameras) {
      const int c = static_cast<int>(camera.camera_id) - 1;
      std::vector<Blob> kept;
      for (size_t b = 0; b < camera.blobs.size(); ++b) {
        const int m = blob_truth[c][b];
        if (m < 0 || !hide(f, m)) kept.push_back(camera.blobs[b]);
      }
      camera.blobs = kept;
    }
    reconstructor.Process(frame_set, tracker.Predict(f), &points);
    samples.clear();
    tracker.Update(f, points, &samples);
    filler.Add(f, samples);
    for (size_t p = 0; p < points.size(); ++p) {
      bool near = false;
      for (size_t m = 0; m < markers.size(); ++m) {
        if ((points[p].point_in_world - markers[m]).norm() >= 5.0) continue;
        result.live_ids[f][m] = tracker.point_identities()[p].id;
        near = true;
      }
      result.live_ghosts += !near;
    }
  }
  filler.Finish();
  result.markers_output = tracker.NumMarkers();
  return result;
}

// Scored by eval's matching (one-to-one, minimum total distance, gated at 20 mm), from first_frame.
MarkerEvalReport Evaluate(const RunResult& run, int first_frame) {
  return testing::EvaluateTrackRows(run.rows, run.truth, run.rate_hz, first_frame);
}

TEST(Tracker, NoisyMotionWithFaultsGivesCleanTrajectories) {
  testing::ProjectionFaults faults;
  faults.noise_px = 0.2;
  faults.occlusion = 0.05;
  faults.occlusion_frames = 5;
  faults.spurious = 2;
  faults.drop_frames = 0.002;
  const RunResult run = RunPipeline(400, 120.0, faults, [](int, int) { return false; });
  const MarkerEvalReport metrics = Evaluate(run, 5);
  EXPECT_LT(metrics.rmse_mm, 1.0);
  EXPECT_LE(metrics.ghosts, 4u);      // 0.01 per frame
  EXPECT_LE(metrics.missing, 2u);     // 0.005 per frame
  EXPECT_EQ(metrics.swaps, 0u);
  EXPECT_LE(run.markers_output, 28);  // 1.2 x 24 markers
  EXPECT_GE(run.markers_output, 24);
}

TEST(Tracker, IdSurvivesFullOcclusionThroughRigidModel) {
  const int hidden = 5;
  const RunResult run = RunPipeline(300, 120.0, testing::ProjectionFaults(),
                            [&](int frame, int marker) { return marker == hidden && frame >= 150 && frame < 190; });
  EXPECT_EQ(run.markers_output, 24);
  // The hidden marker keeps its id: its column holds rigid-model positions near the truth.
  int column = -1;
  for (const TrackSample& s : run.rows.at(140)) {
    if ((s.position - run.truth[140][hidden]).norm() < 5.0) column = s.marker;
  }
  ASSERT_GE(column, 0);
  int predicted = 0;
  for (int frame = 150; frame < 190; ++frame) {
    for (const TrackSample& s : run.rows.at(frame)) {
      if (s.marker != column) continue;
      ++predicted;
      EXPECT_LT((s.position - run.truth[frame][hidden]).norm(), 10.0) << frame;
    }
  }
  EXPECT_GE(predicted, 35);
  for (const TrackSample& s : run.rows.at(200)) {
    if (s.marker == column) {
      EXPECT_LT((s.position - run.truth[200][hidden]).norm(), 2.0);
    }
  }
}

// Every camera loses every marker for 250 ms (the frame sets arrive empty, or none arrive): the
// tracks are held and found again on their predictions, each marker under the id it had before,
// live and in the output columns. (Not yet met: 4 cameras with 0.2 px of noise, where three
// markers of one spinning body trade ids: hub/src/recon/README.md, tracking; an expected failure
// below.)
void ExpectIdsKeptThroughDropOut(bool frame_sets_arrive, int cameras, double noise_px) {
  const double rate_hz = 60.0;
  const int first = 150, last = first + static_cast<int>(0.25 * rate_hz);  // [first, last) lost
  const auto lost = [&](int frame) { return frame >= first && frame < last; };
  testing::ProjectionFaults faults;
  faults.noise_px = noise_px;
  const RunResult run = RunPipeline(
      300, rate_hz, faults, [&](int frame, int) { return frame_sets_arrive && lost(frame); }, {},
      [&](int frame) { return !frame_sets_arrive && lost(frame); }, cameras);
  EXPECT_EQ(run.markers_output, 24);
  const std::vector<uint64_t>& before = run.live_ids[first - 1];
  for (size_t m = 0; m < before.size(); ++m) {
    ASSERT_NE(before[m], 0u) << m;
    for (int frame = first; frame < last; ++frame) EXPECT_EQ(run.live_ids[frame][m], 0u) << frame;
    EXPECT_EQ(run.live_ids[last][m], before[m]) << m;  // found again in the first frame back
    for (int frame = last; frame < 300; ++frame) {
      if (run.live_ids[frame][m] != 0) {
        EXPECT_EQ(run.live_ids[frame][m], before[m]) << m << " " << frame;
      }
    }
  }
  const MarkerEvalReport metrics = Evaluate(run, 5);
  EXPECT_EQ(metrics.swaps, 0u);
  EXPECT_EQ(metrics.ghosts, 0u);
  EXPECT_EQ(run.live_ghosts, 0);
}

TEST(Tracker, IdsKeptThroughADropOutOfEveryCamera) {
  for (const auto& [cameras, noise_px] : {std::pair<int, double>{8, 0.2}, {4, 0.0}}) {
    SCOPED_TRACE(cameras);
    ExpectIdsKeptThroughDropOut(true, cameras, noise_px);
    ExpectIdsKeptThroughDropOut(false, cameras, noise_px);
  }
}

TEST(Tracker, IdsKeptThroughADropOutOfFourNoisyCamerasIsNotMetYet) {
  testing::ExpectFailure("ids kept through a drop-out of every camera, 4 cameras with 0.2 px of noise", [] {
    ExpectIdsKeptThroughDropOut(true, 4, 0.2);
    ExpectIdsKeptThroughDropOut(false, 4, 0.2);
  });
}

TEST(Tracker, GreedyAssignmentAlsoTracks) {
  TrackerOptions options;
  options.assignment = AssignmentMethod::kGreedy;
  testing::ProjectionFaults faults;
  faults.noise_px = 0.2;
  const RunResult run = RunPipeline(200, 120.0, faults, [](int, int) { return false; }, options);
  const MarkerEvalReport metrics = Evaluate(run, 5);
  EXPECT_EQ(run.markers_output, 24);
  EXPECT_EQ(metrics.ghosts, 0u);
  EXPECT_EQ(metrics.swaps, 0u);
}

// A hand of four markers 60 mm apart along its swing swings at 20 mm per frame (50 Hz), then
// accelerates hard: in one frame it moves 50 mm further than predicted, so every marker lands
// 10 mm short of its neighbour's prediction. Nearest-prediction assignment (and the prediction
// pass, which serves each prediction the nearest point) would shift every identity by one
// marker; the limb's common innovation tells them apart. A fifth marker stays still far away.
// Points go straight to the tracker: with_hints emulates the prediction pass (each prediction,
// most trusted first, takes the nearest free point within 1.5 gates).
int SwapsInFastSwing(bool with_hints) {
  TrackerOptions options;
  options.rate_hz = 50.0;
  Tracker tracker(options);
  const int frames = 50;
  const int jump_frame = 30;
  auto truth_at = [&](int f) {
    double x = 20.0 * f;
    if (f >= jump_frame) x += 50.0 * (f - jump_frame + 1);  // 70 mm per frame after the jump
    std::vector<Eigen::Vector3d> markers;
    for (int m = 0; m < 4; ++m) markers.emplace_back(x + 60.0 * m, 0.0, 1000.0);
    markers.emplace_back(0.0, 1500.0, 1000.0);
    return markers;
  };
  std::map<int, int> truth_of_marker;
  int swaps = 0;
  int measured_after_jump = 0;
  std::vector<TrackSample> samples;
  for (int f = 0; f < frames; ++f) {
    const auto truth = truth_at(f);
    std::vector<ReconstructedPoint> points(truth.size());
    for (size_t m = 0; m < truth.size(); ++m) {
      points[m].point_in_world = truth[m];
      points[m].num_views = 6;
    }
    const std::vector<PointPrediction> predictions = tracker.Predict(f);
    if (with_hints) {
      for (const PointPrediction& prediction : predictions) {
        int best = -1;
        double best_distance = 1.5 * prediction.gate_mm;
        for (size_t m = 0; m < points.size(); ++m) {
          const double d = (points[m].point_in_world - prediction.point_in_world).norm();
          if (points[m].track_hint < 0 && d < best_distance) {
            best = static_cast<int>(m);
            best_distance = d;
          }
        }
        if (best >= 0) points[best].track_hint = prediction.track_id;
      }
    }
    samples.clear();
    tracker.Update(f, points, &samples);
    for (const TrackSample& sample : samples) {
      for (size_t m = 0; m < truth.size(); ++m) {
        if ((sample.position - truth_at(static_cast<int>(sample.frame_number))[m]).norm() > 1e-6) continue;
        auto it = truth_of_marker.find(sample.marker);
        if (it != truth_of_marker.end() && it->second != static_cast<int>(m)) ++swaps;
        truth_of_marker[sample.marker] = static_cast<int>(m);
        if (f >= jump_frame && sample.kind == SampleKind::kMeasured) ++measured_after_jump;
      }
    }
  }
  EXPECT_EQ(tracker.NumMarkers(), 5);
  EXPECT_EQ(measured_after_jump, 5 * (frames - jump_frame)) << "with_hints " << with_hints;
  return swaps;
}

TEST(Tracker, FastSwingKeepsIdentities) {
  EXPECT_EQ(SwapsInFastSwing(false), 0);
  EXPECT_EQ(SwapsInFastSwing(true), 0);
}

TEST(TrackerOptions, CheckRejectsBadValues) {
  TrackerOptions options;
  EXPECT_NO_THROW(options.Check());
  options.rate_hz = 0.0;
  EXPECT_THROW(options.Check(), std::invalid_argument);
  options = TrackerOptions();
  options.rigid.min_links_used = 5;
  options.rigid.max_links_used = 4;
  EXPECT_THROW(options.Check(), std::invalid_argument);
}

}  // namespace
}  // namespace mocap

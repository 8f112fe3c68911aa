// One frame set in, 3D marker points out: undistort, serve tracking predictions first (seed 001
// section 3), then run the chosen matcher on the blobs left over. Keeps its buffers between
// frames, so a long session costs no allocations per frame once warmed up.
#pragma once

#include <memory>
#include <vector>

#include <Eigen/Core>

#include "recon/blob_index.h"
#include "recon/contested_groups.h"
#include "recon/frame_views.h"
#include "recon/ghost_filter.h"
#include "recon/matcher.h"
#include "recon/prediction_matcher.h"
#include "recon/recon_options.h"
#include "recon/rig_noise.h"
#include "util/worker_team.h"

namespace mocap {

struct ReconstructedPoint {
  Eigen::Vector3d point_in_world = Eigen::Vector3d::Zero();
  int num_views = 0;
  double rms_px = 0.0;
  int track_hint = -1;  // the prediction's track id when found through a prediction
};

struct ReconstructionStats {
  long long frames = 0;
  long long points = 0;
  long long points_from_predictions = 0;
  long long points_from_contested_groups = 0;  // ContestedGroupResolver's (no track hint)
  long long outlier_views_rejected = 0;
  long long coincident_blobs = 0;  // blobs two predictions fell in, left out of their solves
  long long observations = 0;
  long long leftover_observations = 0;  // not used by a prediction: the matcher's input
  long long unknown_camera_frames = 0;
  long long ghosts_rejected = 0;  // duplicates and points without views of their own
  long long predictions_served_again = 0;  // several threads: a parallel attempt lost a blob
  long long matcher_runs = 0;  // frames in which blobs were left to the matcher (none: not called)
};

// Where a frame's time goes, microseconds of wall clock summed over the frames processed (the
// bench's breakdown; a few clock reads per frame).
struct ReconstructionStageTimes {
  double views_us = 0.0;        // undistortion into observations and rays
  double index_us = 0.0;        // the per-camera blob grid
  double predictions_us = 0.0;  // serving the tracker's predictions
  double groups_us = 0.0;       // resolving contested groups of predictions
  double matcher_us = 0.0;      // matching the blobs left over, completing their points' views
  double ghosts_us = 0.0;       // the ghost filter
};

class Reconstructor {
 public:
  // Checks the options (std::invalid_argument); keeps a reference to the rig.
  Reconstructor(const Rig& rig, const ReconstructorOptions& options);

  void Process(const FrameSet& frame_set, const std::vector<PointPrediction>& predictions,
               std::vector<ReconstructedPoint>* points);

  // The last frame's observations; ray_in_world is set only on those the predictions left.
  const FrameViews& views() const { return views_; }
  const RigModel& rig_model() const { return rig_; }
  const ReconstructionStats& stats() const { return stats_; }
  // The centroid noise (px per image axis) the gates follow now: the configured one, else the
  // calibration's until measured, then the measured one (recon/rig_noise.h). 0: not known yet.
  double centroid_noise_px() const { return gate_noise_px_; }
  // A point's error that noise makes (one sigma, mm, at the working volume): the tracker's
  // measurement noise follows it (Tracker::FollowPointNoise).
  // A point of n views is good to about sqrt(2 / n) of a two-view one's error; the last frame's
  // mean view count stands for n.
  double point_noise_mm() const;
  // The options in force: the configured ones with their gates widened to the noise.
  const ReconstructorOptions& gates() const { return options_; }
  const ReconstructionStageTimes& stage_times() const { return stage_times_; }
  // The last frame's points with the views they were made from (same order as *points).
  const std::vector<TriangulatedPoint>& triangulated() const { return triangulated_; }

 private:
  // Sets the rays of the observations still available to a matcher; returns how many are unused
  // and sets *available to how many a matcher may take.
  int ComputeLeftoverRays(int* available);
  // Runs the matcher on the available observations (first on the seed cameras when many are
  // left) and completes the views of the points it makes.
  void MatchLeftovers(int leftover);
  // Gives the points from `first` on the views their cliques missed.
  void CompleteFrom(size_t first);
  // Widens (or narrows back towards the configured floors) every gate for a centroid noise;
  // a move of under a tenth, or one that leaves the gates where they are, changes nothing.
  void FollowNoise(double sigma_px);

  RigModel rig_;
  ReconstructorOptions configured_;
  double mm_per_px_;
  CentroidNoiseMeter noise_meter_;
  double gate_noise_px_;
  double mean_views_ = 2.0;  // the last frame's points' mean view count
  ReconstructorOptions options_;
  std::unique_ptr<Matcher> matcher_;
  PredictionMatcher prediction_matcher_;
  ContestedGroupResolver group_resolver_;
  GhostFilter ghost_filter_;
  std::vector<char> keep_;
  std::vector<char> seed_mask_;  // empty: acquisition matches over all cameras
  WorkerTeam team_;
  std::vector<int> frame_of_camera_;
  FrameViews views_;
  BlobIndex index_;
  UseCounts used_;
  std::vector<char> shared_;  // blobs two predictions fall in (FindSharedBlobs)
  double median_rms_px_ = 0.0;  // the last frame's median point residual: how precise the rig is
  std::vector<double> rms_scratch_;
  std::vector<TriangulatedPoint> triangulated_;
  std::vector<int> track_ids_;
  ReconstructionStats stats_;
  ReconstructionStageTimes stage_times_;
};

}  // namespace mocap

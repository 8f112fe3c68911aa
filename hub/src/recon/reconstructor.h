// One frame set in, 3D marker points out: undistort, serve tracking predictions first (seed 001
// section 3), then run the chosen matcher on the blobs left over. Keeps its buffers between
// frames, so a long session costs no allocations per frame once warmed up.
#pragma once

#include <memory>
#include <vector>

#include <Eigen/Core>

#include "recon/blob_index.h"
#include "recon/frame_views.h"
#include "recon/ghost_filter.h"
#include "recon/matcher.h"
#include "recon/prediction_matcher.h"
#include "recon/recon_options.h"

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
  long long outlier_views_rejected = 0;
  long long coincident_blobs = 0;  // blobs two predictions fell in, left out of their solves
  long long observations = 0;
  long long leftover_observations = 0;  // not used by a prediction: the matcher's input
  long long unknown_camera_frames = 0;
  long long ghosts_rejected = 0;  // duplicates and points without views of their own
};

class Reconstructor {
 public:
  // Checks the options (std::invalid_argument); keeps a reference to the rig.
  Reconstructor(const Rig& rig, const ReconstructorOptions& options);

  void Process(const FrameSet& frame_set, const std::vector<PointPrediction>& predictions,
               std::vector<ReconstructedPoint>* points);

  const FrameViews& views() const { return views_; }
  const RigModel& rig_model() const { return rig_; }
  const ReconstructionStats& stats() const { return stats_; }
  // The last frame's points with the views they were made from (same order as *points).
  const std::vector<TriangulatedPoint>& triangulated() const { return triangulated_; }

 private:
  RigModel rig_;
  ReconstructorOptions options_;
  std::unique_ptr<Matcher> matcher_;
  PredictionMatcher prediction_matcher_;
  GhostFilter ghost_filter_;
  std::vector<char> keep_;
  FrameViews views_;
  BlobIndex index_;
  UseCounts used_;
  std::vector<char> shared_;  // blobs two predictions fall in (FindSharedBlobs)
  std::vector<TriangulatedPoint> triangulated_;
  std::vector<int> track_ids_;
  ReconstructionStats stats_;
};

}  // namespace mocap

// Temporal shortcut of seed 001 section 3: each tracked marker's predicted 3D position is
// reprojected into every camera and takes the nearest blob within a gate; when those blobs
// triangulate consistently near the prediction, the marker is reconstructed without the graph.
// Blobs left over go to the full matcher.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "recon/blob_index.h"
#include "recon/matcher.h"
#include "util/worker_team.h"

namespace mocap {

struct PointPrediction {
  int track_id = -1;
  Eigen::Vector3d point_in_world = Eigen::Vector3d::Zero();
  // Radius (mm) within which the marker is expected; scales the image gate with depth.
  double gate_mm = 20.0;
};

// Marks in *shared (one entry per observation) every blob that lies within coincident_px
// (pixels) of two or more predictions' reprojections in its camera (see
// PredictionMatchOptions::coincident_px); returns how many. Cameras on the team when given.
// Sets (*contested)[i] for every prediction whose centre lies nearer another's than `factor`
// times the sum of their gates, each gate counted up to gate_cap_mm
// (PredictionMatchOptions::contested_gate_factor, contested_gate_cap_mm); none when factor is 0.
// Cost: a sort and the neighbours along x.
void MarkContested(const std::vector<PointPrediction>& predictions, double factor, double gate_cap_mm,
                   std::vector<char>* contested);

// Whether the point triangulated from `gathered` blobs gathered for `prediction` is a marker
// where the prediction expected one: it keeps most of its views and lands within
// max_shift_factor times the prediction's gate (closer with only two or three views).
bool JudgePredictedPoint(const PredictionMatchOptions& options, const PointPrediction& prediction, size_t gathered,
                         const TriangulatedPoint& point);

int FindSharedBlobs(const RigModel& rig, const FrameViews& views, const BlobIndex& index,
                    const std::vector<PointPrediction>& predictions, double coincident_px, double min_depth_mm,
                    std::vector<char>* shared, WorkerTeam* team = nullptr);

class PredictionMatcher {
 public:
  PredictionMatcher(const PredictionMatchOptions& options,
                    const TriangulationOptions& triangulation_options)
      : options_(options), triangulation_options_(triangulation_options) {}
  // New gates (the rig's noise moved, recon/rig_noise.h); buffers and counts are kept.
  void SetOptions(const PredictionMatchOptions& options, const TriangulationOptions& triangulation_options) {
    options_ = options;
    triangulation_options_ = triangulation_options;
  }

  // Appends the points found to *points and their track ids to *track_ids (parallel arrays).
  // Contested predictions (MarkContested) are skipped: their blobs stay free for the matcher.
  // Predictions are served in the given order: put the most trusted tracks first. With a team
  // of several threads every prediction is first served at once against the blobs free at the
  // start, then committed in order; a prediction one of whose blobs an earlier one took is served
  // again, so the result is the one-thread result exactly.
  // Blobs that `shared` marks (FindSharedBlobs; may be null) are left out of the points' solves.
  void Match(const RigModel& rig, const FrameViews& views, const BlobIndex& index,
             const std::vector<PointPrediction>& predictions, UseCounts* used,
             std::vector<TriangulatedPoint>* points, std::vector<int>* track_ids,
             const std::vector<char>* shared = nullptr, WorkerTeam* team = nullptr);
  // Predictions served again because an earlier one took a blob of their parallel attempt.
  long long served_again() const { return served_again_; }
  // The last Match's contested predictions (MarkContested), one entry per prediction.
  const std::vector<char>& contested() const { return contested_; }

 private:
  // One prediction served: its point, and every blob its searches picked (kept or not): the
  // attempt stands as long as all of those are still free.
  struct Attempt {
    bool served = false;
    TriangulatedPoint point;
    std::vector<int> picked;
  };
  // nearest_[i * cameras + c]: the blob of camera c nearest prediction i within its gate whether
  // used or not, -1 when none (or i contested). Searched camera by camera before any is served.
  void FindNearestBlobs(const RigModel& rig, const BlobIndex& index,
                        const std::vector<PointPrediction>& predictions, WorkerTeam* team);
  // Gathers and triangulates one prediction's blobs; not served when they do not make its marker.
  // Reads only its arguments and nearest_: safe on several threads with different attempts.
  void Serve(const RigModel& rig, const FrameViews& views, const BlobIndex& index,
             const std::vector<PointPrediction>& predictions, size_t which, const UseCounts& used,
             const std::vector<char>* shared, Attempt* attempt) const;
  PredictionMatchOptions options_;
  TriangulationOptions triangulation_options_;
  std::vector<Attempt> speculative_;
  Attempt attempt_;
  std::vector<char> contested_;
  std::vector<int> nearest_;
  long long served_again_ = 0;
};

}  // namespace mocap

// Temporal shortcut of seed 001 section 3: each tracked marker's predicted 3D position is
// reprojected into every camera and takes the nearest blob within a gate; when those blobs
// triangulate consistently near the prediction, the marker is reconstructed without the graph.
// Blobs left over go to the full matcher.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "recon/blob_index.h"
#include "recon/matcher.h"

namespace mocap {

struct PointPrediction {
  int track_id = -1;
  Eigen::Vector3d point_in_world = Eigen::Vector3d::Zero();
  // Radius (mm) within which the marker is expected; scales the image gate with depth.
  double gate_mm = 20.0;
};

// Marks in *shared (one entry per observation) every blob that lies within coincident_px
// (pixels) of two or more predictions' reprojections in its camera (see
// PredictionMatchOptions::coincident_px); returns how many.
int FindSharedBlobs(const RigModel& rig, const FrameViews& views, const BlobIndex& index,
                    const std::vector<PointPrediction>& predictions, double coincident_px, double min_depth_mm,
                    std::vector<char>* shared);

class PredictionMatcher {
 public:
  PredictionMatcher(const PredictionMatchOptions& options,
                    const TriangulationOptions& triangulation_options)
      : options_(options), triangulation_options_(triangulation_options) {}

  // Appends the points found to *points and their track ids to *track_ids (parallel arrays).
  // Predictions are served in the given order: put the most trusted tracks first. Blobs that
  // `shared` marks (FindSharedBlobs; may be null) are left out of the points' solves.
  void Match(const RigModel& rig, const FrameViews& views, const BlobIndex& index,
             const std::vector<PointPrediction>& predictions, UseCounts* used,
             std::vector<TriangulatedPoint>* points, std::vector<int>* track_ids,
             const std::vector<char>* shared = nullptr);

 private:
  // Gathers and triangulates one prediction's blobs: rejected when they do not make its marker,
  // deferred when they make a point nearer another prediction (only those not `served`, when
  // given).
  enum class Outcome { kServed, kRejected, kDeferred };
  Outcome Serve(const RigModel& rig, const FrameViews& views, const BlobIndex& index,
             const std::vector<PointPrediction>& predictions, size_t which, const UseCounts& used,
             const std::vector<char>* served, const std::vector<char>* shared, TriangulatedPoint* point);

  PredictionMatchOptions options_;
  TriangulationOptions triangulation_options_;
  std::vector<int> gathered_;
  std::vector<size_t> deferred_;
  std::vector<char> served_;
};

}  // namespace mocap

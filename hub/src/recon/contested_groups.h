// Contested predictions (MarkContested: close markers of a dense cluster whose gates overlap)
// resolved jointly instead of by the full matcher. The contested predictions fall into groups
// (connected components of the contested pairs); in each camera a group's predictions and the
// free blobs within their gates are paired by an optimal assignment (util/assignment.h, cost:
// squared distance in units of the prediction's gate), so two predictions never take one blob
// and a blob between them goes to the nearer. Each prediction's blobs are then triangulated
// (TriangulateRobust: a view that disagrees with the others is dropped), completed with the
// free blobs near the point's reprojection (CompleteViews) and judged like a served prediction
// (JudgePredictedPoint). A point kept carries no track hint: as with the matcher's points, the
// tracker's assignment names it, so a group whose assignment came out permuted in every camera
// still makes the right points. Blobs no point kept stay free for the matcher.
#pragma once

#include <vector>

#include "recon/blob_index.h"
#include "recon/matcher.h"
#include "recon/prediction_matcher.h"

namespace mocap {

// Groups of contested predictions: two contested predictions share a group when their centres
// lie nearer than contested_gate_factor times the sum of their gates (each counted up to
// contested_gate_cap_mm), transitively. Fills *group_begin (groups + 1 offsets) and *members
// (prediction indices, each group in index order: older tracks first). Predictions not marked
// in `contested` belong to no group.
void FindContestedGroups(const std::vector<PointPrediction>& predictions, const std::vector<char>& contested,
                         double factor, double gate_cap_mm, std::vector<int>* group_begin, std::vector<int>* members);

class ContestedGroupResolver {
 public:
  ContestedGroupResolver(const PredictionMatchOptions& options, const TriangulationOptions& triangulation)
      : options_(options), triangulation_(triangulation) {}
  // New gates (the rig's noise moved, recon/rig_noise.h).
  void SetOptions(const PredictionMatchOptions& options, const TriangulationOptions& triangulation) {
    options_ = options;
    triangulation_ = triangulation;
  }

  // Appends the points made for the contested predictions to *points, marks their blobs used;
  // returns how many. `shared` as in PredictionMatcher::Match (may be null).
  int Resolve(const RigModel& rig, const FrameViews& views, const BlobIndex& index,
              const std::vector<PointPrediction>& predictions, const std::vector<char>& contested, UseCounts* used,
              std::vector<TriangulatedPoint>* points, const std::vector<char>* shared = nullptr);
  long long groups() const { return groups_; }

 private:
  // Pairs one group's predictions with camera c's free blobs: (*assigned)[k] for member k.
  void AssignInCamera(const RigModel& rig, const FrameViews& views, const BlobIndex& index,
                      const std::vector<PointPrediction>& predictions, const int* members, int count, int camera,
                      const UseCounts& used);

  PredictionMatchOptions options_;
  TriangulationOptions triangulation_;
  std::vector<int> group_begin_, members_;
  // Per member of the group being resolved, per camera: the blob assigned, -1 none.
  std::vector<int> assigned_;
  std::vector<int> candidates_;
  std::vector<int> picked_;
  TriangulatedPoint point_;
  long long groups_ = 0;
};

}  // namespace mocap

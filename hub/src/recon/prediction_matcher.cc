// Prediction reprojection, gated nearest-blob search, and consistency checks.
#include "recon/prediction_matcher.h"

#include <algorithm>
#include <cmath>

namespace mocap {

namespace {

// True when another prediction not yet served (served may be null: none is) lies clearly closer
// to `point` (at most half as far) than prediction `own`: the blobs near `own` belonged to a neighbour (in a dense
// cluster, a prediction whose marker is hidden in some views gathers its neighbour's blobs
// there, and the neighbour's prediction would then take this marker's blobs: the two would
// trade identities).
bool CloserToAnother(const std::vector<PointPrediction>& predictions, size_t own, const Eigen::Vector3d& point,
                     const std::vector<char>* served) {
  const double limit2 = 0.25 * (point - predictions[own].point_in_world).squaredNorm();
  for (size_t j = 0; j < predictions.size(); ++j) {
    if (j == own || (served != nullptr && (*served)[j])) continue;
    if ((point - predictions[j].point_in_world).squaredNorm() < limit2) return true;
  }
  return false;
}

}  // namespace

int FindSharedBlobs(const RigModel& rig, const FrameViews& views, const BlobIndex& index,
                    const std::vector<PointPrediction>& predictions, double coincident_px, double min_depth_mm,
                    std::vector<char>* shared) {
  shared->assign(views.observations.size(), 0);
  if (!(coincident_px > 0.0) || predictions.size() < 2) return 0;
  int found = 0;
  for (int c = 0; c < rig.NumCameras(); ++c) {
    const CameraModel& cam = rig.camera(c);
    for (const PointPrediction& prediction : predictions) {
      const Eigen::Vector3d p = cam.cam_from_world_rotation * prediction.point_in_world + cam.cam_from_world_translation;
      if (!(p.z() > min_depth_mm)) continue;
      // 1: one prediction near the blob so far; 2: two or more.
      index.ForEachWithin(views, c, p.head<2>() / p.z(), coincident_px / cam.focal_px, [&](int o, double) {
        char& mark = (*shared)[static_cast<size_t>(o)];
        if (mark < 2) found += ++mark == 2;
      });
    }
  }
  for (char& mark : *shared) mark = mark == 2;
  return found;
}

PredictionMatcher::Outcome PredictionMatcher::Serve(const RigModel& rig, const FrameViews& views, const BlobIndex& index,
                              const std::vector<PointPrediction>& predictions, size_t which, const UseCounts& used,
                              const std::vector<char>* served, const std::vector<char>* shared,
                              TriangulatedPoint* point) {
  const PointPrediction& prediction = predictions[which];
  const int num_cameras = rig.NumCameras();
  gathered_.clear();
  for (int c = 0; c < num_cameras; ++c) {
    const CameraModel& cam = rig.camera(c);
    const Eigen::Vector3d p =
        cam.cam_from_world_rotation * prediction.point_in_world + cam.cam_from_world_translation;
    if (!(p.z() > triangulation_options_.min_depth_mm)) continue;
    const double gate_px = std::clamp(cam.focal_px * prediction.gate_mm / p.z(),
                                      options_.min_gate_px, options_.max_gate_px);
    const int best = index.Nearest(views, c, p.head<2>() / p.z(), gate_px / cam.focal_px, [&](int o) {
      return IsAvailable(views.observations[o], used[o]);
    });
    if (best >= 0) gathered_.push_back(best);
  }
  if (static_cast<int>(gathered_.size()) < triangulation_options_.min_views) return Outcome::kRejected;
  if (!TriangulateRobust(rig, views, gathered_, triangulation_options_, point, shared)) return Outcome::kRejected;
  CompleteViews(rig, views, index, used, triangulation_options_, point, shared);
  const size_t kept = point->observations.size();
  // Two views left out of many gathered: the prediction collected other markers' blobs and two
  // of them happen to agree. A real marker keeps most of its views.
  if (kept == 2 && gathered_.size() >= 4) return Outcome::kRejected;
  // A marker seen in only two views could be two other markers' blobs that happen to fall in
  // the gates; the shift check bounds how far such a combination may land.
  // Few views leave a wrong blob near an epipolar line free to drag the point along it; such a
  // point must stay closer to the prediction.
  const double factor = kept == 2 ? 0.5 * options_.max_shift_factor
                        : kept == 3 ? 0.75 * options_.max_shift_factor
                                    : options_.max_shift_factor;
  const double max_shift = factor * prediction.gate_mm;
  if ((point->point_in_world - prediction.point_in_world).norm() > max_shift) return Outcome::kRejected;
  if (!options_.defer_contested) return Outcome::kServed;
  return CloserToAnother(predictions, which, point->point_in_world, served) ? Outcome::kDeferred : Outcome::kServed;
}

void PredictionMatcher::Match(const RigModel& rig, const FrameViews& views, const BlobIndex& index,
                              const std::vector<PointPrediction>& predictions, UseCounts* used,
                              std::vector<TriangulatedPoint>* points, std::vector<int>* track_ids,
                              const std::vector<char>* shared) {
  TriangulatedPoint point;
  deferred_.clear();
  served_.assign(predictions.size(), 0);
  for (size_t i = 0; i < predictions.size(); ++i) {
    const Outcome outcome = Serve(rig, views, index, predictions, i, *used, nullptr, shared, &point);
    if (outcome == Outcome::kServed) {
      served_[i] = 1;
      MarkUsed(point, used);
      points->push_back(point);
      track_ids->push_back(predictions[i].track_id);
    } else if (outcome == Outcome::kDeferred) {
      deferred_.push_back(i);
    }
  }
  // A second chance once the others took their blobs: a prediction that gathered a neighbour's
  // blobs now finds its own. Only predictions still unserved can claim its point now (a fast
  // marker may land near a track that already has its own point); two predictions that took
  // each other's markers both stay unserved, for the matcher and the tracker.
  for (size_t i : deferred_) {
    if (Serve(rig, views, index, predictions, i, *used, &served_, shared, &point) == Outcome::kServed) {
      served_[i] = 1;
      MarkUsed(point, used);
      points->push_back(point);
      track_ids->push_back(predictions[i].track_id);
    }
  }
}

}  // namespace mocap

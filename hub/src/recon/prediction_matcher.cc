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
                    std::vector<char>* shared, WorkerTeam* team) {
  shared->assign(views.observations.size(), 0);
  if (!(coincident_px > 0.0) || predictions.size() < 2) return 0;
  // Each camera marks only its own observations: cameras may run on several threads.
  const auto mark_camera = [&](int c) {
    const CameraModel& cam = rig.camera(c);
    for (const PointPrediction& prediction : predictions) {
      const Eigen::Vector3d p = cam.cam_from_world_rotation * prediction.point_in_world + cam.cam_from_world_translation;
      if (!(p.z() > min_depth_mm)) continue;
      // 1: one prediction near the blob so far; 2: two or more.
      index.ForEachWithin(views, c, p.head<2>() / p.z(), coincident_px / cam.focal_px, [&](int o, double) {
        char& mark = (*shared)[static_cast<size_t>(o)];
        if (mark < 2) ++mark;
      });
    }
  };
  if (team != nullptr) {
    team->Run(rig.NumCameras(), mark_camera);
  } else {
    for (int c = 0; c < rig.NumCameras(); ++c) mark_camera(c);
  }
  int found = 0;
  for (char& mark : *shared) {
    mark = mark == 2;
    found += mark;
  }
  return found;
}

void PredictionMatcher::Serve(const RigModel& rig, const FrameViews& views, const BlobIndex& index,
                              const std::vector<PointPrediction>& predictions, size_t which, const UseCounts& used,
                              const std::vector<char>* served, const std::vector<char>* shared,
                              Attempt* attempt) const {
  const PointPrediction& prediction = predictions[which];
  const int num_cameras = rig.NumCameras();
  std::vector<int>& picked = attempt->picked;
  picked.clear();
  attempt->outcome = Outcome::kRejected;
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
    if (best >= 0) picked.push_back(best);
  }
  const size_t gathered = picked.size();
  if (static_cast<int>(gathered) < triangulation_options_.min_views) return;
  if (!TriangulateRobust(rig, views, picked, triangulation_options_, &attempt->point, shared)) return;
  CompleteViews(rig, views, index, used, triangulation_options_, &attempt->point, shared, &picked);
  attempt->outcome = Judge(predictions, which, served, gathered, attempt->point);
}

PredictionMatcher::Outcome PredictionMatcher::Judge(const std::vector<PointPrediction>& predictions, size_t which,
                                                    const std::vector<char>* served, size_t gathered,
                                                    const TriangulatedPoint& point) const {
  const PointPrediction& prediction = predictions[which];
  const size_t kept = point.observations.size();
  // Two views left out of many gathered: the prediction collected other markers' blobs and two
  // of them happen to agree. A real marker keeps most of its views.
  if (kept == 2 && gathered >= 4) return Outcome::kRejected;
  // A marker seen in only two views could be two other markers' blobs that happen to fall in
  // the gates; the shift check bounds how far such a combination may land.
  // Few views leave a wrong blob near an epipolar line free to drag the point along it; such a
  // point must stay closer to the prediction.
  const double factor = kept == 2 ? 0.5 * options_.max_shift_factor
                        : kept == 3 ? 0.75 * options_.max_shift_factor
                                    : options_.max_shift_factor;
  const double max_shift = factor * prediction.gate_mm;
  if ((point.point_in_world - prediction.point_in_world).norm() > max_shift) return Outcome::kRejected;
  if (!options_.defer_contested) return Outcome::kServed;
  return CloserToAnother(predictions, which, point.point_in_world, served) ? Outcome::kDeferred : Outcome::kServed;
}

void PredictionMatcher::Match(const RigModel& rig, const FrameViews& views, const BlobIndex& index,
                              const std::vector<PointPrediction>& predictions, UseCounts* used,
                              std::vector<TriangulatedPoint>* points, std::vector<int>* track_ids,
                              const std::vector<char>* shared, WorkerTeam* team) {
  deferred_.clear();
  served_.assign(predictions.size(), 0);
  const bool speculate = team != nullptr && team->threads() > 1 && predictions.size() > 1;
  if (speculate) {
    speculative_.resize(predictions.size());
    const UseCounts& at_start = *used;
    team->Run(static_cast<int>(predictions.size()), [&](int i) {
      Serve(rig, views, index, predictions, static_cast<size_t>(i), at_start, nullptr, shared, &speculative_[i]);
    });
  }
  const auto still_free = [&](const Attempt& attempt) {
    for (int o : attempt.picked) {
      if (!IsAvailable(views.observations[o], (*used)[o])) return false;
    }
    return true;
  };
  for (size_t i = 0; i < predictions.size(); ++i) {
    const Attempt* attempt = &attempt_;
    if (speculate && still_free(speculative_[i])) {
      attempt = &speculative_[i];
    } else {
      served_again_ += speculate;
      Serve(rig, views, index, predictions, i, *used, nullptr, shared, &attempt_);
    }
    if (attempt->outcome == Outcome::kServed) {
      served_[i] = 1;
      MarkUsed(attempt->point, used);
      points->push_back(attempt->point);
      track_ids->push_back(predictions[i].track_id);
    } else if (attempt->outcome == Outcome::kDeferred) {
      deferred_.push_back(i);
    }
  }
  // A second chance once the others took their blobs: a prediction that gathered a neighbour's
  // blobs now finds its own. Only predictions still unserved can claim its point now (a fast
  // marker may land near a track that already has its own point); two predictions that took
  // each other's markers both stay unserved, for the matcher and the tracker.
  for (size_t i : deferred_) {
    Serve(rig, views, index, predictions, i, *used, &served_, shared, &attempt_);
    if (attempt_.outcome == Outcome::kServed) {
      served_[i] = 1;
      MarkUsed(attempt_.point, used);
      points->push_back(attempt_.point);
      track_ids->push_back(predictions[i].track_id);
    }
  }
}

}  // namespace mocap

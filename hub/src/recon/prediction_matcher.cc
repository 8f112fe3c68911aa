// Prediction reprojection, gated nearest-blob search, and consistency checks.
#include "recon/prediction_matcher.h"

#include <algorithm>
#include <cmath>

namespace mocap {

void MarkContested(const std::vector<PointPrediction>& predictions, double factor, double gate_cap_mm,
                   std::vector<char>* contested) {
  contested->assign(predictions.size(), 0);
  if (!(factor > 0.0) || predictions.size() < 2) return;
  // Sweep along x: a pair can only be contested while their x distance is under the factor
  // times their gates, so each prediction meets only its neighbours along x.
  // Last call's order, sorted again by insertion: tracks move little from frame to frame, so it
  // is nearly sorted already. But a prediction's index is its track's rank by age, and one track
  // ending shifts every younger one: past a budget of moves (or with a count that changed) it is
  // sorted from scratch instead.
  thread_local std::vector<size_t> by_x;
  const auto x_of = [&](size_t i) { return predictions[i].point_in_world.x(); };
  const auto sort_from_scratch = [&] {
    by_x.resize(predictions.size());
    for (size_t i = 0; i < by_x.size(); ++i) by_x[i] = i;
    std::sort(by_x.begin(), by_x.end(), [&](size_t a, size_t b) { return x_of(a) < x_of(b); });
  };
  if (by_x.size() != predictions.size()) sort_from_scratch();
  size_t budget = 4 * by_x.size();
  for (size_t i = 1; i < by_x.size(); ++i) {
    const size_t moving = by_x[i];
    size_t j = i;
    for (; j > 0 && x_of(by_x[j - 1]) > x_of(moving) && budget > 0; --j, --budget) by_x[j] = by_x[j - 1];
    by_x[j] = moving;
    if (budget == 0) {
      sort_from_scratch();
      break;
    }
  }
  const auto gate_of = [&](const PointPrediction& p) { return std::min(p.gate_mm, gate_cap_mm); };
  double max_gate = 0.0;
  for (const PointPrediction& p : predictions) max_gate = std::max(max_gate, gate_of(p));
  for (size_t a = 0; a < by_x.size(); ++a) {
    const PointPrediction& first = predictions[by_x[a]];
    const double reach = factor * (gate_of(first) + max_gate);
    for (size_t b = a + 1; b < by_x.size(); ++b) {
      const PointPrediction& second = predictions[by_x[b]];
      if (second.point_in_world.x() - first.point_in_world.x() > reach) break;
      const double limit = factor * (gate_of(first) + gate_of(second));
      if ((second.point_in_world - first.point_in_world).squaredNorm() < limit * limit)
        (*contested)[by_x[a]] = (*contested)[by_x[b]] = 1;
    }
  }
}


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

namespace {

// A prediction reprojected into one camera: the centre and radius (normalized units) of its gate.
struct GatedReprojection {
  bool in_front = false;
  Eigen::Vector2d normalized;
  double radius = 0.0;
};

// Inlined into the loop over all predictions, whose divisions then overlap.
[[gnu::always_inline]] inline GatedReprojection Reproject(const CameraModel& cam, const PointPrediction& prediction,
                                                          const PredictionMatchOptions& options,
                                                          double min_depth_mm) {
  GatedReprojection gate;
  const Eigen::Vector3d p = cam.cam_from_world_rotation * prediction.point_in_world + cam.cam_from_world_translation;
  gate.in_front = p.z() > min_depth_mm;
  if (!gate.in_front) return gate;
  const double gate_px = std::clamp(cam.focal_px * prediction.gate_mm / p.z(), options.min_gate_px, options.max_gate_px);
  gate.normalized = p.head<2>() / p.z();
  gate.radius = gate_px / cam.focal_px;
  return gate;
}

}  // namespace

void PredictionMatcher::FindNearestBlobs(const RigModel& rig, const BlobIndex& index,
                                         const std::vector<PointPrediction>& predictions, WorkerTeam* team) {
  const int num_cameras = rig.NumCameras();
  nearest_.resize(predictions.size() * static_cast<size_t>(num_cameras));
  // One camera at a time: its grid stays in cache for all the predictions' searches there
  // (prediction after prediction, every search went to another camera's grid). The gates of all
  // predictions first, then the searches: the divisions then overlap instead of each waiting
  // behind the previous search's branches.
  const auto search_camera = [&](int c) {
    const CameraModel& cam = rig.camera(c);
    thread_local std::vector<GatedReprojection> gates;
    gates.resize(predictions.size());
    for (size_t i = 0; i < predictions.size(); ++i) {
      gates[i] = Reproject(cam, predictions[i], options_, triangulation_options_.min_depth_mm);
    }
    for (size_t i = 0; i < predictions.size(); ++i) {
      int& nearest = nearest_[i * num_cameras + c];
      nearest = -1;
      const GatedReprojection& gate = gates[i];
      if (gate.in_front && !contested_[i]) {
        nearest = index.NearestOfAll(c, gate.normalized, gate.radius);
      }
    }
  };
  if (team != nullptr) {
    team->Run(num_cameras, search_camera);
  } else {
    for (int c = 0; c < num_cameras; ++c) search_camera(c);
  }
}

void PredictionMatcher::Serve(const RigModel& rig, const FrameViews& views, const BlobIndex& index,
                              const std::vector<PointPrediction>& predictions, size_t which, const UseCounts& used,
                              const std::vector<char>* shared, Attempt* attempt) const {
  const int num_cameras = rig.NumCameras();
  std::vector<int>& picked = attempt->picked;
  picked.clear();
  attempt->served = false;
  const int* nearest = nearest_.data() + which * num_cameras;
  for (int c = 0; c < num_cameras; ++c) {
    int best = nearest[c];
    // The nearest blob of all, when still free, is the nearest free one (ties go to the lower
    // index either way); only when an earlier point took it does the gate need a second search.
    if (best >= 0 && !IsAvailable(views.observations[best], used[best])) {
      const GatedReprojection gate =
          Reproject(rig.camera(c), predictions[which], options_, triangulation_options_.min_depth_mm);
      best = index.Nearest(views, c, gate.normalized, gate.radius, [&](int o) {
        return IsAvailable(views.observations[o], used[o]);
      });
    }
    if (best >= 0) picked.push_back(best);
  }
  const size_t gathered = picked.size();
  if (static_cast<int>(gathered) < triangulation_options_.min_views) return;
  if (!TriangulateRobust(rig, views, picked, triangulation_options_, &attempt->point, shared)) return;
  CompleteViews(rig, views, index, used, triangulation_options_, &attempt->point, shared, &picked);
  attempt->served = JudgePredictedPoint(options_, predictions[which], gathered, attempt->point);
}

bool JudgePredictedPoint(const PredictionMatchOptions& options, const PointPrediction& prediction, size_t gathered,
                         const TriangulatedPoint& point) {
  const size_t kept = point.observations.size();
  // Two views left out of many gathered: the prediction collected other markers' blobs and two
  // of them happen to agree. A real marker keeps most of its views.
  if (kept == 2 && gathered >= 4) return false;
  // A marker seen in only two views could be two other markers' blobs that happen to fall in
  // the gates; the shift check bounds how far such a combination may land.
  // Few views leave a wrong blob near an epipolar line free to drag the point along it; such a
  // point must stay closer to the prediction.
  const double factor = kept == 2 ? 0.5 * options.max_shift_factor
                        : kept == 3 ? 0.75 * options.max_shift_factor
                                    : options.max_shift_factor;
  return (point.point_in_world - prediction.point_in_world).norm() <= factor * prediction.gate_mm;
}

void PredictionMatcher::Match(const RigModel& rig, const FrameViews& views, const BlobIndex& index,
                              const std::vector<PointPrediction>& predictions, UseCounts* used,
                              std::vector<TriangulatedPoint>* points, std::vector<int>* track_ids,
                              const std::vector<char>* shared, WorkerTeam* team) {
  MarkContested(predictions, options_.contested_gate_factor, options_.contested_gate_cap_mm, &contested_);
  FindNearestBlobs(rig, index, predictions, team);
  const bool speculate = team != nullptr && team->threads() > 1 && predictions.size() > 1;
  if (speculate) {
    speculative_.resize(predictions.size());
    const UseCounts& at_start = *used;
    team->Run(static_cast<int>(predictions.size()), [&](int i) {
      if (!contested_[i]) Serve(rig, views, index, predictions, static_cast<size_t>(i), at_start, shared, &speculative_[i]);
    });
  }
  const auto still_free = [&](const Attempt& attempt) {
    for (int o : attempt.picked) {
      if (!IsAvailable(views.observations[o], (*used)[o])) return false;
    }
    return true;
  };
  for (size_t i = 0; i < predictions.size(); ++i) {
    if (contested_[i]) continue;
    const Attempt* attempt = &attempt_;
    if (speculate && still_free(speculative_[i])) {
      attempt = &speculative_[i];
    } else {
      served_again_ += speculate;
      Serve(rig, views, index, predictions, i, *used, shared, &attempt_);
    }
    if (!attempt->served) continue;
    MarkUsed(attempt->point, used);
    points->push_back(attempt->point);
    track_ids->push_back(predictions[i].track_id);
  }
}

}  // namespace mocap

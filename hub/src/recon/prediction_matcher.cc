// Prediction reprojection, gated nearest-blob search, and consistency checks.
#include "recon/prediction_matcher.h"

#include <algorithm>
#include <cmath>

namespace mocap {

void PredictionMatcher::Match(const RigModel& rig, const FrameViews& views,
                              const std::vector<PointPrediction>& predictions, UseCounts* used,
                              std::vector<TriangulatedPoint>* points, std::vector<int>* track_ids) {
  const int num_cameras = rig.NumCameras();
  sorted_by_x_.resize(num_cameras);
  for (int c = 0; c < num_cameras; ++c) {
    std::vector<int>& sorted = sorted_by_x_[c];
    sorted.clear();
    for (int i = views.camera_begin[c]; i < views.camera_begin[c + 1]; ++i) sorted.push_back(i);
    std::sort(sorted.begin(), sorted.end(), [&](int a, int b) {
      return views.observations[a].normalized.x() < views.observations[b].normalized.x();
    });
  }

  std::vector<int> gathered;
  TriangulatedPoint point;
  for (const PointPrediction& prediction : predictions) {
    gathered.clear();
    for (int c = 0; c < num_cameras; ++c) {
      const CameraModel& cam = rig.camera(c);
      const Eigen::Vector3d p =
          cam.cam_from_world_rotation * prediction.point_in_world + cam.cam_from_world_translation;
      if (!(p.z() > triangulation_options_.min_depth_mm)) continue;
      const Eigen::Vector2d projected = p.head<2>() / p.z();
      const double gate_px = std::clamp(cam.focal_px * prediction.gate_mm / p.z(),
                                        options_.min_gate_px, options_.max_gate_px);
      const double gate = gate_px / cam.focal_px;  // in normalized units
      const std::vector<int>& sorted = sorted_by_x_[c];
      auto it = std::lower_bound(sorted.begin(), sorted.end(), projected.x() - gate,
                                 [&](int index, double x) {
                                   return views.observations[index].normalized.x() < x;
                                 });
      int best = -1;
      double best_distance = gate * gate;
      for (; it != sorted.end(); ++it) {
        const Observation& obs = views.observations[*it];
        if (obs.normalized.x() > projected.x() + gate) break;
        const double d2 = (obs.normalized - projected).squaredNorm();
        if (d2 <= best_distance) {
          best_distance = d2;
          best = *it;
        }
      }
      if (best >= 0 && IsAvailable(views.observations[best], (*used)[best])) {
        gathered.push_back(best);
      }
    }
    if (static_cast<int>(gathered.size()) < triangulation_options_.min_views) continue;
    if (!TriangulateRobust(rig, views, gathered, triangulation_options_, &point)) continue;
    // A marker seen in only two views could be two other markers' blobs that happen to fall in
    // the gates; the shift check bounds how far such a combination may land.
    if ((point.point_in_world - prediction.point_in_world).norm() >
        options_.max_shift_factor * prediction.gate_mm) {
      continue;
    }
    MarkUsed(point, used);
    points->push_back(point);
    track_ids->push_back(prediction.track_id);
  }
}

}  // namespace mocap

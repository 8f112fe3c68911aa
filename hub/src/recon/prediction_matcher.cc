// Prediction reprojection, gated nearest-blob search, and consistency checks.
#include "recon/prediction_matcher.h"

#include <algorithm>
#include <cmath>

namespace mocap {

void PredictionMatcher::Match(const RigModel& rig, const FrameViews& views, const BlobIndex& index,
                              const std::vector<PointPrediction>& predictions, UseCounts* used,
                              std::vector<TriangulatedPoint>* points, std::vector<int>* track_ids) {
  const int num_cameras = rig.NumCameras();
  std::vector<int> gathered;
  TriangulatedPoint point;
  for (const PointPrediction& prediction : predictions) {
    gathered.clear();
    for (int c = 0; c < num_cameras; ++c) {
      const CameraModel& cam = rig.camera(c);
      const Eigen::Vector3d p =
          cam.cam_from_world_rotation * prediction.point_in_world + cam.cam_from_world_translation;
      if (!(p.z() > triangulation_options_.min_depth_mm)) continue;
      const double gate_px = std::clamp(cam.focal_px * prediction.gate_mm / p.z(),
                                        options_.min_gate_px, options_.max_gate_px);
      const int best = index.Nearest(views, c, p.head<2>() / p.z(), gate_px / cam.focal_px, [&](int o) {
        return IsAvailable(views.observations[o], (*used)[o]);
      });
      if (best >= 0) gathered.push_back(best);
    }
    if (static_cast<int>(gathered.size()) < triangulation_options_.min_views) continue;
    if (!TriangulateRobust(rig, views, gathered, triangulation_options_, &point)) continue;
    CompleteViews(rig, views, index, *used, triangulation_options_, &point);
    const size_t kept = point.observations.size();
    // Two views left out of many gathered: the prediction collected other markers' blobs and two
    // of them happen to agree. A real marker keeps most of its views.
    if (kept == 2 && gathered.size() >= 4) continue;
    // A marker seen in only two views could be two other markers' blobs that happen to fall in
    // the gates; the shift check bounds how far such a combination may land.
    // Few views leave a wrong blob near an epipolar line free to drag the point along it; such a
    // point must stay closer to the prediction.
    const double factor = kept == 2 ? 0.5 * options_.max_shift_factor
                          : kept == 3 ? 0.75 * options_.max_shift_factor
                                      : options_.max_shift_factor;
    const double max_shift = factor * prediction.gate_mm;
    if ((point.point_in_world - prediction.point_in_world).norm() > max_shift) continue;
    MarkUsed(point, used);
    points->push_back(point);
    track_ids->push_back(prediction.track_id);
  }
}

}  // namespace mocap

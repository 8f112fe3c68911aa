// Duplicate and ghost rejection over one frame's points.
#include "recon/ghost_filter.h"

#include <algorithm>
#include <numeric>

namespace mocap {

void GhostFilter::MarkExplained(const RigModel& rig, const FrameViews& views, const BlobIndex& index,
                                const TriangulatedPoint& point) {
  // Where the point has a view, that view is its blob there (a merged one may be shared, and is
  // then marked by both points); elsewhere any blob near its reprojection is its unclaimed image.
  has_view_.assign(rig.NumCameras(), 0);
  for (int o : point.observations) {
    explained_[o] = 1;
    has_view_[views.observations[o].camera] = 1;
  }
  for (int c = 0; c < rig.NumCameras(); ++c) {
    if (has_view_[c]) continue;
    const CameraModel& cam = rig.camera(c);
    const Eigen::Vector3d p = cam.cam_from_world_rotation * point.point_in_world + cam.cam_from_world_translation;
    if (!(p.z() > triangulation_.min_depth_mm)) continue;
    const Eigen::Vector2d at = p.head<2>() / p.z();
    const double merged_radius = triangulation_.max_merged_px / cam.focal_px;
    const double radius = triangulation_.max_reprojection_px / cam.focal_px;
    index.ForEachWithin(views, c, at, merged_radius, [&](int o, double distance) {
      if (distance <= radius || (views.observations[o].flags & kBlobMerged)) explained_[o] = 1;
    });
  }
}

int GhostFilter::Apply(const RigModel& rig, const FrameViews& views, const BlobIndex& index,
                       const std::vector<TriangulatedPoint>& points, size_t tracked, UseCounts* used,
                       std::vector<char>* keep) {
  const int count = static_cast<int>(points.size());
  keep->assign(count, 1);
  if (!options_.enabled) return 0;
  order_.resize(count);
  std::iota(order_.begin(), order_.end(), 0);
  std::stable_sort(order_.begin(), order_.end(), [&](int a, int b) {
    return points[a].observations.size() > points[b].observations.size();
  });
  explained_.assign(views.NumObservations(), 0);
  kept_.clear();
  const double min_separation2 = options_.min_separation_mm * options_.min_separation_mm;
  int dropped = 0;
  for (int i : order_) {
    const TriangulatedPoint& point = points[i];
    bool duplicate = false;
    for (int k : kept_) {
      if ((points[k].point_in_world - point.point_in_world).squaredNorm() < min_separation2) {
        duplicate = true;
        break;
      }
    }
    int evidence = 0;
    for (int o : point.observations) evidence += explained_[o] ? 0 : 1;
    const bool ghost = static_cast<size_t>(i) >= tracked && evidence < triangulation_.min_views;
    if (duplicate || ghost) {
      (*keep)[i] = 0;
      for (int o : point.observations) --(*used)[o];
      ++dropped;
      continue;
    }
    kept_.push_back(i);
    MarkExplained(rig, views, index, point);
  }
  return dropped;
}

}  // namespace mocap

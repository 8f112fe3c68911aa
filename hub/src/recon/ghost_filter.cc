// Duplicate and ghost rejection over one frame's points.
#include "recon/ghost_filter.h"

#include <algorithm>
#include <numeric>

#include "util/counting_sort.h"

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
    const double merged_radius = triangulation_.MergedLimitPx() / cam.focal_px;
    const double radius = triangulation_.max_reprojection_px / cam.focal_px;
    index.ForEachWithin(views, c, at, merged_radius, [&](int o, double distance) {
      if (distance <= radius || (views.observations[o].flags & kBlobMerged)) explained_[o] = 1;
    });
  }
}

void GhostFilter::OrderByViews(const std::vector<TriangulatedPoint>& points) {
  // Counting sort on the number of views, most first: stable (equal counts keep their order, the
  // predictions of the oldest tracks first) without the merge buffer of std::stable_sort.
  int most = 0;
  for (const TriangulatedPoint& point : points) most = std::max(most, static_cast<int>(point.observations.size()));
  order_.resize(points.size());
  CountingSort(
      static_cast<int>(points.size()), most + 1,
      [&](int i) { return most - static_cast<int>(points[i].observations.size()); }, &by_views_begin_,
      [&](int i, int slot) { order_[slot] = i; });
}

int GhostFilter::Apply(const RigModel& rig, const FrameViews& views, const BlobIndex& index,
                       const std::vector<TriangulatedPoint>& points, size_t tracked, UseCounts* used,
                       std::vector<char>* keep) {
  const int count = static_cast<int>(points.size());
  keep->assign(count, 1);
  if (!options_.enabled) return 0;
  OrderByViews(points);
  // Only untracked points take the evidence test: after the last of them in the order, what the
  // kept points explain is read by no one and is not marked (in steady state every point is
  // tracked, and the marking would cost a blob search per camera a point has no view in).
  size_t mark_until = 0;
  for (size_t position = 0; position < order_.size(); ++position) {
    if (static_cast<size_t>(order_[position]) >= tracked) mark_until = position;
  }
  if (static_cast<size_t>(count) > tracked) explained_.assign(views.NumObservations(), 0);
  kept_positions_.clear();
  const double min_separation2 = options_.min_separation_mm * options_.min_separation_mm;
  int dropped = 0;
  for (size_t position = 0; position < order_.size(); ++position) {
    const int i = order_[position];
    const TriangulatedPoint& point = points[i];
    bool duplicate = false;
    for (const Eigen::Vector3d& kept : kept_positions_) {
      if ((kept - point.point_in_world).squaredNorm() < min_separation2) {
        duplicate = true;
        break;
      }
    }
    const bool untracked = static_cast<size_t>(i) >= tracked;
    bool ghost = false;
    if (untracked) {
      int evidence = 0;
      for (int o : point.observations) evidence += explained_[o] ? 0 : 1;
      ghost = evidence < triangulation_.min_views;
    }
    if (duplicate || ghost) {
      (*keep)[i] = 0;
      for (int o : point.observations) --(*used)[o];
      ++dropped;
      continue;
    }
    kept_positions_.push_back(point.point_in_world);
    if (position < mark_until) MarkExplained(rig, views, index, point);
  }
  return dropped;
}

}  // namespace mocap

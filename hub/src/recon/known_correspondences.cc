// True views by reprojection, then the recon layer's own robust triangulation per marker.
#include "recon/known_correspondences.h"

#include <cmath>

#include "ingest/camera_frame.h"

namespace mocap {

void FindTrueViews(const RigModel& rig, const FrameViews& views, const std::vector<Eigen::Vector3d>& truth,
                   const KnownCorrespondenceOptions& options, std::vector<std::vector<int>>* views_of_marker) {
  views_of_marker->assign(truth.size(), {});
  for (int c = 0; c < rig.NumCameras(); ++c) {
    const CameraModel& cam = rig.camera(c);
    const double limit = options.max_px / cam.focal_px;
    for (size_t m = 0; m < truth.size(); ++m) {
      if (!truth[m].allFinite()) continue;
      const Eigen::Vector3d p = cam.cam_from_world_rotation * truth[m] + cam.cam_from_world_translation;
      if (!(p.z() > 0.0)) continue;
      const Eigen::Vector2d projected = p.head<2>() / p.z();
      int best = -1;
      double best_distance = limit;
      for (int o = views.camera_begin[c]; o < views.camera_begin[c + 1]; ++o) {
        const Observation& observation = views.observations[o];
        if (options.skip_merged && (observation.flags & kBlobMerged)) continue;
        const double d = (observation.normalized - projected).norm();
        if (d < best_distance) {
          best_distance = d;
          best = o;
        }
      }
      if (best >= 0) (*views_of_marker)[m].push_back(best);
    }
  }
}

size_t TriangulateKnownCorrespondences(const RigModel& rig, const FrameViews& views,
                                       const std::vector<std::vector<int>>& views_of_marker,
                                       const TriangulationOptions& options,
                                       std::vector<Eigen::Vector3d>* positions) {
  positions->assign(views_of_marker.size(), Eigen::Vector3d::Constant(std::nan("")));
  TriangulatedPoint point;
  size_t triangulated = 0;
  for (size_t m = 0; m < views_of_marker.size(); ++m) {
    if (static_cast<int>(views_of_marker[m].size()) < options.min_views) continue;
    if (!TriangulateRobust(rig, views, views_of_marker[m], options, &point)) continue;
    (*positions)[m] = point.point_in_world;
    ++triangulated;
  }
  return triangulated;
}

}  // namespace mocap

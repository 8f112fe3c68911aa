// Blob index and view completion.
#include "recon/blob_index.h"

#include <algorithm>
#include <numeric>

namespace mocap {

void BlobIndex::Build(const RigModel& rig, const FrameViews& views) {
  const int num_cameras = rig.NumCameras();
  sorted_by_x_.resize(num_cameras);
  x_.resize(num_cameras);
  for (int c = 0; c < num_cameras; ++c) {
    std::vector<int>& sorted = sorted_by_x_[c];
    sorted.resize(views.camera_begin[c + 1] - views.camera_begin[c]);
    std::iota(sorted.begin(), sorted.end(), views.camera_begin[c]);
    std::sort(sorted.begin(), sorted.end(), [&](int a, int b) {
      return views.observations[a].normalized.x() < views.observations[b].normalized.x();
    });
    x_[c].resize(sorted.size());
    for (size_t k = 0; k < sorted.size(); ++k) x_[c][k] = views.observations[sorted[k]].normalized.x();
  }
}

void CompleteViews(const RigModel& rig, const FrameViews& views, const BlobIndex& index,
                   const UseCounts& used, const TriangulationOptions& options, TriangulatedPoint* point,
                   const std::vector<char>* shared) {
  const int num_cameras = rig.NumCameras();
  std::vector<char> has_camera(num_cameras, 0);
  for (int o : point->observations) has_camera[views.observations[o].camera] = 1;
  std::vector<int> extended = point->observations;
  for (int c = 0; c < num_cameras; ++c) {
    if (has_camera[c]) continue;
    const CameraModel& cam = rig.camera(c);
    const Eigen::Vector3d p = cam.cam_from_world_rotation * point->point_in_world + cam.cam_from_world_translation;
    if (!(p.z() > options.min_depth_mm)) continue;
    const int found = index.Nearest(views, c, p.head<2>() / p.z(), options.max_reprojection_px / cam.focal_px,
                                    [&](int o) { return IsAvailable(views.observations[o], used[o]); });
    if (found >= 0) extended.push_back(found);
  }
  if (extended.size() == point->observations.size()) return;
  TriangulatedPoint completed;
  // The extra views were chosen within the residual limit; if the joint solve disagrees, the
  // original point stands.
  if (TriangulateRobust(rig, views, extended, options, &completed, shared) &&
      completed.observations.size() > point->observations.size()) {
    completed.rejected.insert(completed.rejected.begin(), point->rejected.begin(), point->rejected.end());
    *point = completed;
  }
}

}  // namespace mocap

// Per-camera caches and per-frame undistortion of blobs into observations.
#include "recon/frame_views.h"

#include <Eigen/Geometry>

namespace mocap {

RigModel::RigModel(const Rig& rig) {
  cameras_.reserve(rig.cameras.size());
  for (const Camera& camera : rig.cameras) {
    CameraModel model;
    model.camera = &camera;
    model.undistorter = std::make_shared<const Undistorter>(camera);
    model.cam_from_world_rotation = camera.rotation;
    model.cam_from_world_translation = camera.translation;
    model.center_in_world = camera.CenterInWorld();
    model.focal_px = 0.5 * (camera.intrinsics.fx + camera.intrinsics.fy);
    index_of_id_[camera.id] = static_cast<int>(cameras_.size());
    cameras_.push_back(model);
  }
}

int RigModel::IndexOf(uint32_t camera_id) const {
  const auto it = index_of_id_.find(camera_id);
  return it == index_of_id_.end() ? -1 : it->second;
}

void LayoutFrameViews(const RigModel& rig, const FrameSet& frame_set, FrameViews* views,
                      std::vector<int>* frame_of_camera) {
  views->frame_number = frame_set.frame_number;
  views->observations.clear();
  views->skipped_unknown_cameras = 0;
  const int num_cameras = rig.NumCameras();
  views->camera_begin.assign(num_cameras + 1, 0);

  // Counting pass first so observations can be laid out grouped by camera index even when the
  // frame set lists cameras in arrival order.
  frame_of_camera->assign(num_cameras, -1);
  for (int f = 0; f < static_cast<int>(frame_set.cameras.size()); ++f) {
    const int index = rig.IndexOf(frame_set.cameras[f].camera_id);
    if (index < 0) {
      ++views->skipped_unknown_cameras;
      continue;
    }
    (*frame_of_camera)[index] = f;
  }
  int total = 0;
  for (int c = 0; c < num_cameras; ++c) {
    views->camera_begin[c] = total;
    if ((*frame_of_camera)[c] >= 0) {
      total += static_cast<int>(frame_set.cameras[(*frame_of_camera)[c]].blobs.size());
    }
  }
  views->camera_begin[num_cameras] = total;
  views->observations.resize(total);
}

namespace {

// Inlined into UndistortCamera's loop (a call per blob costs a few percent of undistortion).
inline Eigen::Vector3d RayOf(const CameraModel& model, const Eigen::Vector2d& normalized) {
  return (model.cam_from_world_rotation.transpose() * normalized.homogeneous()).normalized();
}

}  // namespace

void ComputeRay(const RigModel& rig, Observation* observation) {
  observation->ray_in_world = RayOf(rig.camera(observation->camera), observation->normalized);
}

void UndistortCamera(const RigModel& rig, const FrameSet& frame_set, const std::vector<int>& frame_of_camera,
                     int camera, FrameViews* views, bool with_rays) {
  if (frame_of_camera[camera] < 0) return;
  const CameraModel& model = rig.camera(camera);
  const std::vector<Blob>& blobs = frame_set.cameras[frame_of_camera[camera]].blobs;
  for (int b = 0; b < static_cast<int>(blobs.size()); ++b) {
    Observation& obs = views->observations[views->camera_begin[camera] + b];
    obs.camera = camera;
    obs.blob = b;
    obs.flags = blobs[b].flags;
    obs.normalized = model.undistorter->Undistort(blobs[b].pixel);
    if (with_rays) obs.ray_in_world = RayOf(model, obs.normalized);
  }
}

void BuildFrameViews(const RigModel& rig, const FrameSet& frame_set, FrameViews* views) {
  std::vector<int> frame_of_camera;
  LayoutFrameViews(rig, frame_set, views, &frame_of_camera);
  for (int c = 0; c < rig.NumCameras(); ++c) UndistortCamera(rig, frame_set, frame_of_camera, c, views);
}

}  // namespace mocap

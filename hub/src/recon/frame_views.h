// Undistortion of one frame set: every blob becomes an observation with undistorted normalized
// coordinates and a world ray. RigModel caches per-camera quantities so a frame costs one
// undistortion per blob and nothing else. Frames of cameras absent from the rig are skipped.
#pragma once

#include <cstdint>
#include <memory>
#include <unordered_map>
#include <vector>

#include <Eigen/Core>

#include "geometry/camera.h"
#include "ingest/camera_frame.h"
#include "recon/undistorter.h"

namespace mocap {

struct CameraModel {
  const Camera* camera = nullptr;
  std::shared_ptr<const Undistorter> undistorter;
  Eigen::Matrix3d cam_from_world_rotation = Eigen::Matrix3d::Identity();
  Eigen::Vector3d cam_from_world_translation = Eigen::Vector3d::Zero();
  Eigen::Vector3d center_in_world = Eigen::Vector3d::Zero();
  // Pixels per unit of normalized image coordinate: converts normalized residuals to px.
  double focal_px = 1.0;
};

// The rig as used by reconstruction. Keeps a pointer to each Camera: the Rig must outlive it.
class RigModel {
 public:
  explicit RigModel(const Rig& rig);

  int NumCameras() const { return static_cast<int>(cameras_.size()); }
  const CameraModel& camera(int index) const { return cameras_[index]; }
  // -1 when the id is not in the rig.
  int IndexOf(uint32_t camera_id) const;

 private:
  std::vector<CameraModel> cameras_;
  std::unordered_map<uint32_t, int> index_of_id_;
};

struct Observation {
  int camera = 0;  // index into RigModel
  int blob = 0;    // index into that camera's CameraFrame::blobs
  uint32_t flags = 0;
  Eigen::Vector2d normalized = Eigen::Vector2d::Zero();  // undistorted
  Eigen::Vector3d ray_in_world = Eigen::Vector3d::UnitZ();  // unit direction from the centre
};

// All observations of one frame set, grouped by camera: observations of camera c are
// [camera_begin[c], camera_begin[c + 1]).
struct FrameViews {
  uint64_t frame_number = 0;
  std::vector<Observation> observations;
  std::vector<int> camera_begin;
  int skipped_unknown_cameras = 0;

  int NumObservations() const { return static_cast<int>(observations.size()); }
};

// Refills *views from the frame set (reuses its memory between frames).
void BuildFrameViews(const RigModel& rig, const FrameSet& frame_set, FrameViews* views);

// BuildFrameViews in two steps, for callers that undistort cameras on several threads: the
// layout (camera ranges; *frame_of_camera gets each rig camera's index in frame_set.cameras or
// -1), then each camera on its own (different cameras write disjoint ranges).
void LayoutFrameViews(const RigModel& rig, const FrameSet& frame_set, FrameViews* views,
                      std::vector<int>* frame_of_camera);
// with_rays false leaves ray_in_world to ComputeRay: only the matchers read rays, and after the
// prediction pass they see a few dozen of a frame's ~1000 blobs.
void UndistortCamera(const RigModel& rig, const FrameSet& frame_set, const std::vector<int>& frame_of_camera,
                     int camera, FrameViews* views, bool with_rays = true);
// Sets the observation's ray_in_world from its camera and undistorted coordinates.
void ComputeRay(const RigModel& rig, Observation* observation);

}  // namespace mocap

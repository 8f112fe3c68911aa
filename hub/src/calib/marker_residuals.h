// What continuous calibration learns from an ordinary capture: reconstructed markers with their
// 2D views, and per camera the reprojection residuals of those views. MarkerResidualCollector
// runs the reconstruction on frame sets and keeps each point (at least min_views views) with
// the blobs that made it and, for every other camera the point projects into, the nearest blob
// there when it is unambiguous: a camera that moved (its views rejected by the reconstruction)
// still has its observations, only further from where the calibration puts them.
//
// Every frame set that gave samples also leaves its blobs (FrameBlobs): a camera knocked far
// enough that its nearest blobs are not its markers is found again from them
// (camera_relocalization.h).
//
// A camera's residual of one view is leave-one-out: the point is triangulated again from the
// other cameras' views the reconstruction used, then projected into this camera. So a moved
// camera does not pull its own points, and the figure measures the camera alone.
//
// Threads: none; one object per thread. Error policy: options Check() throws
// std::invalid_argument; data never throws (frames of unknown cameras are skipped).
#pragma once

#include <cstdint>
#include <deque>
#include <memory>
#include <vector>

#include <Eigen/Core>

#include "geometry/camera.h"
#include "geometry/triangulation.h"
#include "ingest/camera_frame.h"
#include "recon/reconstructor.h"

namespace mocap {

struct MarkerView {
  int camera = 0;                                        // index into the rig's cameras
  Eigen::Vector2d pixel = Eigen::Vector2d::Zero();       // observed, distorted
  Eigen::Vector2d normalized = Eigen::Vector2d::Zero();  // undistorted (intrinsics are not refined)
  bool reconstructed = false;  // one of the views the reconstruction made the point from
};

struct MarkerSample {
  uint64_t frame = 0;
  Eigen::Vector3d point_in_world = Eigen::Vector3d::Zero();
  std::vector<MarkerView> views;
};

// The blobs of one frame set, per camera (rig order; empty for a camera without a frame).
struct FrameBlobs {
  uint64_t frame = 0;
  std::vector<std::vector<Eigen::Vector2d>> pixels;  // distorted, px
};

struct MarkerResidualOptions {
  int min_views = 3;               // points made from fewer views are not kept
  double max_point_rms_px = 1.0;   // nor points the reconstruction fitted worse than this
  // A camera that did not take part gets the nearest blob within this radius of the point's
  // projection, when the second nearest is at least ambiguity_ratio times further away.
  double search_px = 40.0;
  double ambiguity_ratio = 2.0;
  size_t max_samples = 200000;     // the oldest samples are dropped beyond this (bounded memory)
  size_t max_blob_frames = 5000;   // frame sets whose blobs are kept (the oldest dropped beyond)

  void Check() const;
};

class MarkerResidualCollector {
 public:
  // The rig must outlive the collector. Throws std::invalid_argument on bad options (also the
  // reconstruction's, which are used by Add()).
  MarkerResidualCollector(const Rig& rig, const MarkerResidualOptions& options,
                          const ReconstructorOptions& recon = ReconstructorOptions());

  // Reconstructs one frame set and appends its points (dropping the oldest beyond max_samples).
  void Add(const FrameSet& set);
  // Appends the points another reconstructor (of the same rig) just made of `set`, as `serve`'s
  // live reconstruction does: no second reconstruction.
  void AddReconstructed(const FrameSet& set, const Reconstructor& reconstructor);
  // Drops the samples and blobs of frames before `frame` (a sliding window).
  void DropBefore(uint64_t frame);
  const std::deque<MarkerSample>& samples() const { return samples_; }
  std::deque<MarkerSample>* mutable_samples() { return &samples_; }
  // In frame order, one per frame set that gave at least one sample.
  const std::deque<FrameBlobs>& blobs() const { return blobs_; }
  std::deque<FrameBlobs>* mutable_blobs() { return &blobs_; }
  uint64_t frames() const { return frames_; }

 private:
  const Rig& rig_;
  MarkerResidualOptions options_;
  ReconstructorOptions recon_;
  std::unique_ptr<Reconstructor> reconstructor_;  // made on the first Add()
  std::deque<MarkerSample> samples_;
  std::deque<FrameBlobs> blobs_;
  std::vector<const CameraFrame*> frame_of_camera_;
  std::vector<ReconstructedPoint> points_;
  uint64_t frames_ = 0;
};

// One camera's leave-one-out residuals over a set of samples.
struct CameraResiduals {
  uint32_t camera_id = 0;
  size_t observations = 0;       // views with a leave-one-out point
  size_t reconstructed = 0;      // of which the reconstruction had used
  double median_px = 0.0;        // median residual length
  double rms_px = 0.0;           // root mean square residual length (the hub's rms_px)
  Eigen::Vector2d mean_px = Eigen::Vector2d::Zero();  // mean residual vector (observed - projected)
};

// The triangulation input of one view: the camera's pose and the view's undistorted coordinates.
PointView ViewThrough(const Camera& camera, const Eigen::Vector2d& normalized);

// Leave-one-out point of `sample` for view `skip` (index into sample.views), triangulated from
// the other reconstructed views of cameras not in `excluded` (may be empty); false with fewer
// than two such views.
bool LeaveOneOutPoint(const Rig& rig, const MarkerSample& sample, int skip, const std::vector<char>& excluded,
                      Eigen::Vector3d* point_in_world);

// Per camera (rig order) residuals of every view of the samples under `rig`.
std::vector<CameraResiduals> ComputeCameraResiduals(const Rig& rig, const std::deque<MarkerSample>& samples);

}  // namespace mocap

// Continuous calibration: camera poses refined from an ordinary capture. The markers of the
// capture are unknown points (marker_residuals.h gathers them with their views); the cameras
// whose residuals say they moved (bump_detector.h) are re-solved while every other camera is
// held, so the scale and world frame stay those of the existing calibration. Each moved camera
// is first found again alone from its blobs and the points the held cameras triangulate
// (camera_relocalization.h: shift vote, PnP + RANSAC, narrowing re-pairing; not from the old
// pose, whose nearest blobs are wrong pairings after a knock of a degree or more); its views are
// then paired again under the found pose, and the moved cameras and all points are refined
// jointly (Huber loss, outlier views dropped). A new pose is accepted only when it brings the camera's
// residuals back to the rig's level and by a clear factor; a rig where nothing moved is
// returned unchanged, bit for bit.
//
// Error policy: options Check() throws std::invalid_argument; a rig where too many cameras
// moved to hold the gauge throws std::runtime_error with what to do.
#pragma once

#include <deque>
#include <string>
#include <vector>

#include "calib/bump_detector.h"
#include "calib/camera_relocalization.h"
#include "calib/marker_residuals.h"
#include "geometry/camera.h"

namespace mocap {

struct ExtrinsicRefinementOptions {
  BumpDetectionOptions detection;
  CameraRelocalizationOptions relocalization;
  bool refine_drifting = true;     // drifting cameras are re-solved like bumped ones
  double loss_scale_px = 1.0;      // Huber scale of the joint solve
  double outlier_px = 1.5;         // views beyond max(this, 5 robust sigma) are dropped
  size_t max_points = 20000;       // samples in the joint solve (spread evenly over the input)
  double min_improvement = 2.0;    // median residual must fall by this factor to accept
  int max_iterations = 100;
  int num_threads = 1;

  void Check() const;
};

struct CameraRefinement {
  uint32_t camera_id = 0;
  CameraPoseState state_before = CameraPoseState::kUnknown;
  CameraPoseState state_after = CameraPoseState::kUnknown;
  CameraResiduals before;
  CameraResiduals after;         // under the returned rig
  bool refined = false;          // re-solved (it had moved)
  bool accepted = false;         // its new pose is in the returned rig
  double centre_change_mm = 0.0;  // of the solved pose against the old one
  double rotation_change_deg = 0.0;
  size_t inlier_views = 0;       // views of the camera in the joint solve
  size_t outlier_views = 0;      // views dropped as outliers
  CameraRelocalization relocalization;  // the robust first pose (when refined)
  std::string note;              // why a solved pose was refused, and what to do
};

struct ExtrinsicRefinement {
  Rig rig;                       // the input rig with the accepted poses
  double baseline_px = 0.0;
  size_t samples = 0;            // marker samples given
  size_t points_solved = 0;      // points in the joint solve (0 when nothing moved)
  std::vector<CameraRefinement> cameras;  // rig order

  bool Changed() const;
};

// `blobs`: the frames' blobs the samples came with (MarkerResidualCollector::blobs()), from
// which a moved camera is found again and its views paired anew.
ExtrinsicRefinement RefineExtrinsics(const Rig& rig, const std::deque<MarkerSample>& samples,
                                     const std::deque<FrameBlobs>& blobs, const ExtrinsicRefinementOptions& options);

}  // namespace mocap

// Extrinsics from one marker (or a hand-held light) waved through the volume, as easyWand and
// low-cost systems do, with the scale from a known distance. A multi-stage solve (the model is
// WandSolver, wand_calibration.h):
//   1. views (wand_observations.h, WandGeometry::SingleMarker): a camera frame with exactly one
//      blob after static reflections are masked;
//   2. the camera-pair graph: the reference camera has the most views; the others join one at a
//      time through the posed camera they share the most frames with: the pair's essential
//      matrix (OpenCV five-point RANSAC on undistorted points) and recoverPose give its rotation
//      and the direction of its baseline; the baseline's length is chained from the points the
//      posed cameras already triangulate (median depth ratio in the partner camera);
//   3. bundle adjustment (Ceres, Huber loss, Schur): every camera pose but the reference's, a
//      point per frame; the first joiner's distance from the reference is held (the gauge of an
//      unscaled solve); views beyond max(outlier_px, 5 robust sigma) are dropped, then solved again;
//   4. scale: frames in which cameras see exactly two blobs (a bar of known length, or the wand)
//      are triangulated with the solved cameras (each view's end order chosen by the epipolar
//      error against the first view) and the median length sets the scale.
// The world frame is the reference camera's (`calibrate world` levels it).
// Error policy: options Check() throws std::invalid_argument; data that cannot give a
// calibration throws std::runtime_error with the reason and what to do.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "calib/wand_observations.h"
#include "geometry/camera.h"
#include "ingest/camera_frame.h"

namespace mocap {

struct SingleMarkerOptions {
  double scale_length_mm = 0.0;     // distance between the scale bar's two markers (required)
  WandSelectionOptions selection;
  int min_pair_frames = 30;         // a camera joins through a partner sharing at least this many
  double ransac_px = 1.0;           // essential-matrix RANSAC threshold
  double loss_scale_px = 1.0;       // Huber scale of the bundle adjustment
  double outlier_px = 1.0;          // views beyond max(this, 5 robust sigma) leave the solve
  size_t min_scale_frames = 10;     // two-blob frames needed for the scale
  size_t max_frames = 20000;        // single-marker frames in the solve (spread evenly)
  int max_iterations = 200;
  int num_threads = 1;

  void Check() const;
};

struct SingleMarkerCamera {
  uint32_t id = 0;
  size_t views = 0;        // single-marker views selected
  size_t used = 0;         // views in the final solve
  double rms_px = 0.0;     // reprojection RMS of the used views (the hub's rms_px)
  uint32_t joined_through = 0;  // the posed camera it joined through (0 for the reference)
};

struct SingleMarkerResult {
  Rig rig;                         // the intrinsics given, the solved poses (world: the reference's)
  uint32_t reference_id = 0;
  size_t frames_selected = 0;      // frames with a single-marker view in 2+ cameras
  size_t frames_used = 0;          // points in the final solve
  size_t scale_frames = 0;         // two-blob frames triangulated for the scale
  double scale_length_rms_mm = 0.0;  // RMS error of their lengths after scaling
  std::vector<SingleMarkerCamera> cameras;  // rig order
};

// `frames`: the session's frame sets; `intrinsics`: the cameras (intrinsics are held).
SingleMarkerResult CalibrateSingleMarker(const std::vector<FrameSet>& frames, const Rig& intrinsics,
                                         const SingleMarkerOptions& options);

}  // namespace mocap

// Does a calibration fit a recorded session? The session's frame sets (a sample spread over it)
// are reconstructed with the calibration, and every camera's leave-one-out residuals
// (marker_residuals.h) over the points seen by at least three cameras are judged against the
// others' (bump_detector.h): a camera whose median residual is far above the rig's baseline, above
// an absolute floor and above a multiple of the centroid noise the calibration states for it
// (Camera::centroid_rms_px) does not fit: it was moved, turned or swapped since that calibration.
// `reconstruct` refuses such a calibration with the per-camera residuals that show it.
// Threads: none. Error policy: options Check() throws std::invalid_argument; data never throws.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "calib/bump_detector.h"
#include "calib/marker_residuals.h"
#include "geometry/camera.h"
#include "ingest/camera_frame.h"
#include "recon/recon_options.h"

namespace mocap {

struct CalibrationFitOptions {
  size_t frame_sets = 300;    // frame sets judged, spread evenly over the session
  // Leave-one-out residuals: a camera the calibration places wrongly has its views rejected by
  // the reconstruction, so its nearest blobs are searched this far from the projections (a turn of
  // a few degrees moves markers by tens of pixels).
  MarkerResidualOptions residuals = [] {
    MarkerResidualOptions r;
    r.search_px = 150.0;
    return r;
  }();
  // A camera does not fit when its median residual is above judge.bump_px, above
  // judge.drift_factor x the median of the cameras' medians, and above noise_factor x its stated
  // centroid noise.
  BumpDetectionOptions judge;
  double noise_factor = 5.0;

  void Check() const;  // std::invalid_argument naming the field
};

struct CameraFit {
  CameraResiduals residuals;
  size_t blobs = 0;        // the camera's blobs in the judged frame sets
  double limit_px = 0.0;   // its median residual above this: does not fit
  bool judged = false;     // enough observations (judge.min_observations)
  bool fits = true;
};

struct CalibrationFit {
  size_t frame_sets = 0;   // judged
  size_t points = 0;       // points of at least residuals.min_views views
  double baseline_px = 0.0;
  std::vector<CameraFit> cameras;  // rig order

  bool Fits() const;
  // "camera 3 median 48.20 px over 412 views (limit 2.00 px)" for each camera that does not fit,
  // joined with "; "; empty when all fit.
  std::string Misfits() const;
  // Every camera: "1: 0.21 px (812 views)", joined with ", " (unjudged: "n/a (12 views of its 3400 blobs)").
  std::string PerCamera() const;
};

class CalibrationFitCheck {
 public:
  // The rig must outlive the check. Throws std::invalid_argument on bad options.
  CalibrationFitCheck(const Rig& rig, const CalibrationFitOptions& options, const ReconstructorOptions& recon);
  // One frame set of the sample, reconstructed without predictions.
  void Add(const FrameSet& set);
  CalibrationFit Judge() const;

 private:
  const Rig& rig_;
  CalibrationFitOptions options_;
  MarkerResidualCollector collector_;
  std::vector<size_t> blobs_;  // per camera (rig order)
  size_t frame_sets_ = 0;
};

// The noisiest camera's stated centroid noise lets the sample keep points fitted up to 3 times it
// (a webcam rig's points are never within 1 px).
MarkerResidualOptions ResidualOptionsFor(const Rig& rig, MarkerResidualOptions residuals);

}  // namespace mocap

// A calibration judged against a session's blobs: leave-one-out residuals per camera.
#include "calib/calibration_fit.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace mocap {

void CalibrationFitOptions::Check() const {
  if (frame_sets < 1) throw std::invalid_argument("calibration fit: frame_sets must be >= 1");
  if (!(noise_factor >= 1.0) || !std::isfinite(noise_factor))
    throw std::invalid_argument("calibration fit: noise_factor must be >= 1");
  residuals.Check();
  judge.Check();
}

MarkerResidualOptions ResidualOptionsFor(const Rig& rig, MarkerResidualOptions residuals) {
  double noisiest = 0.0;
  for (const Camera& camera : rig.cameras) noisiest = std::max(noisiest, camera.centroid_rms_px);
  residuals.max_point_rms_px = std::max(residuals.max_point_rms_px, 3.0 * noisiest);
  return residuals;
}

CalibrationFitCheck::CalibrationFitCheck(const Rig& rig, const CalibrationFitOptions& options,
                                         const ReconstructorOptions& recon)
    : rig_(rig),
      options_(options),
      collector_(rig, ResidualOptionsFor(rig, options.residuals),
                 [&recon] {
                   ReconstructorOptions r = recon;
                   r.use_predictions = false;
                   return r;
                 }()),
      blobs_(rig.cameras.size(), 0) {
  options_.Check();
}

void CalibrationFitCheck::Add(const FrameSet& set) {
  collector_.Add(set);
  ++frame_sets_;
  for (const CameraFrame& frame : set.cameras) {
    for (size_t c = 0; c < rig_.cameras.size(); ++c) {
      if (rig_.cameras[c].id == frame.camera_id) blobs_[c] += frame.blobs.size();
    }
  }
}

CalibrationFit CalibrationFitCheck::Judge() const {
  CalibrationFit fit;
  fit.frame_sets = frame_sets_;
  fit.points = collector_.samples().size();
  const BumpDetection detection = DetectBumps(ComputeCameraResiduals(rig_, collector_.samples()), options_.judge);
  fit.baseline_px = detection.baseline_px;
  for (size_t c = 0; c < detection.cameras.size(); ++c) {
    const CameraVerdict& verdict = detection.cameras[c];
    CameraFit camera;
    camera.residuals = verdict.residuals;
    camera.blobs = blobs_[c];
    camera.limit_px = std::max({options_.judge.bump_px, options_.judge.drift_factor * detection.baseline_px,
                                options_.noise_factor * rig_.cameras[c].centroid_rms_px});
    camera.judged = verdict.state != CameraPoseState::kUnknown;
    camera.fits = !camera.judged || !(camera.residuals.median_px > camera.limit_px);
    fit.cameras.push_back(camera);
  }
  return fit;
}

bool CalibrationFit::Fits() const {
  return std::all_of(cameras.begin(), cameras.end(), [](const CameraFit& c) { return c.fits; });
}

std::string CalibrationFit::Misfits() const {
  std::string text;
  char line[160];
  for (const CameraFit& c : cameras) {
    if (c.fits) continue;
    std::snprintf(line, sizeof line, "%scamera %u median %.2f px over %zu views (limit %.2f px)", text.empty() ? "" : "; ",
                  c.residuals.camera_id, c.residuals.median_px, c.residuals.observations, c.limit_px);
    text += line;
  }
  return text;
}

std::string CalibrationFit::PerCamera() const {
  std::string text;
  char line[96];
  for (const CameraFit& c : cameras) {
    if (c.judged) {
      std::snprintf(line, sizeof line, "%s%u: %.2f px (%zu views)", text.empty() ? "" : ", ", c.residuals.camera_id,
                    c.residuals.median_px, c.residuals.observations);
    } else {
      std::snprintf(line, sizeof line, "%s%u: n/a (%zu views of its %zu blobs)", text.empty() ? "" : ", ",
                    c.residuals.camera_id, c.residuals.observations, c.blobs);
    }
    text += line;
  }
  return text;
}

}  // namespace mocap

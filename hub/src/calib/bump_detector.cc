// Per-camera verdicts from leave-one-out residuals.
#include "calib/bump_detector.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace mocap {

const char* CameraPoseStateName(CameraPoseState state) {
  switch (state) {
    case CameraPoseState::kUnknown: return "unknown";
    case CameraPoseState::kOk: return "ok";
    case CameraPoseState::kDrifting: return "drifting";
    case CameraPoseState::kBumped: return "bumped";
  }
  return "unknown";
}

void BumpDetectionOptions::Check() const {
  if (min_observations < 1) throw std::invalid_argument("min_observations must be >= 1");
  if (!(drift_px > 0.0) || !std::isfinite(drift_px)) throw std::invalid_argument("drift_px must be > 0");
  if (!(drift_factor >= 1.0) || !std::isfinite(drift_factor)) throw std::invalid_argument("drift_factor must be >= 1");
  if (!(bump_px >= drift_px) || !std::isfinite(bump_px)) throw std::invalid_argument("bump_px must be >= drift_px");
  if (!(baseline_px >= 0.0) || !std::isfinite(baseline_px)) throw std::invalid_argument("baseline_px must be >= 0");
}

bool BumpDetection::AnyMoved() const {
  for (const CameraVerdict& c : cameras) {
    if (c.state == CameraPoseState::kDrifting || c.state == CameraPoseState::kBumped) return true;
  }
  return false;
}

BumpDetection DetectBumps(const std::vector<CameraResiduals>& residuals, const BumpDetectionOptions& options) {
  options.Check();
  BumpDetection detection;
  std::vector<double> medians;
  for (const CameraResiduals& r : residuals) {
    if (r.observations >= options.min_observations) medians.push_back(r.median_px);
  }
  if (options.baseline_px > 0.0) {
    detection.baseline_px = options.baseline_px;
  } else if (!medians.empty()) {
    std::nth_element(medians.begin(), medians.begin() + medians.size() / 2, medians.end());
    detection.baseline_px = medians[medians.size() / 2];
  }
  const double drift_limit = std::max(options.drift_px, options.drift_factor * detection.baseline_px);
  const double bump_limit = std::max(options.bump_px, options.drift_factor * detection.baseline_px);
  for (const CameraResiduals& r : residuals) {
    CameraVerdict verdict;
    verdict.camera_id = r.camera_id;
    verdict.residuals = r;
    if (r.observations < options.min_observations) {
      verdict.state = CameraPoseState::kUnknown;
    } else if (r.median_px > bump_limit) {
      verdict.state = CameraPoseState::kBumped;
    } else if (r.median_px > drift_limit) {
      verdict.state = CameraPoseState::kDrifting;
    } else {
      verdict.state = CameraPoseState::kOk;
    }
    detection.cameras.push_back(verdict);
  }
  return detection;
}

}  // namespace mocap

// Which cameras moved since calibration, judged from their leave-one-out residuals
// (marker_residuals.h) against the rig's baseline: the median of the cameras' median residuals
// (most cameras of a rig are where the calibration says), or a baseline the caller knows (the
// residual of the calibration itself). A camera well above it is drifting; one far above it
// (a pose change of a few tenths of a degree moves every marker by pixels) is bumped. The verdict
// is the shift in the image, not the size of the move: a turn about the optical axis moves
// markers near the image centre by little (0.5 deg: about 1 px at 120 px from it), so such a
// camera is drifting, and re-solved alike.
// Pure functions; options Check() throws std::invalid_argument.
#pragma once

#include <string>
#include <vector>

#include "calib/marker_residuals.h"

namespace mocap {

enum class CameraPoseState { kUnknown, kOk, kDrifting, kBumped };
// "unknown" (too few observations), "ok", "drifting", "bumped".
const char* CameraPoseStateName(CameraPoseState state);

struct BumpDetectionOptions {
  size_t min_observations = 30;  // fewer views: kUnknown
  // Drifting: median residual above drift_px and above drift_factor x the baseline.
  double drift_px = 0.5;
  double drift_factor = 2.5;
  // Bumped: median residual above bump_px (and above drift_factor x the baseline).
  double bump_px = 2.0;
  // Baseline median residual in px; 0: the median over the cameras with enough observations.
  double baseline_px = 0.0;

  void Check() const;
};

struct CameraVerdict {
  uint32_t camera_id = 0;
  CameraPoseState state = CameraPoseState::kUnknown;
  CameraResiduals residuals;
};

struct BumpDetection {
  double baseline_px = 0.0;
  std::vector<CameraVerdict> cameras;  // rig order

  bool AnyMoved() const;  // a camera drifting or bumped
};

BumpDetection DetectBumps(const std::vector<CameraResiduals>& residuals, const BumpDetectionOptions& options);

}  // namespace mocap

// What an operator asks of a live wanding (POST /api/calibration/wand/start; ServiceApi's
// StartWanding): the session to record, the wand, when collection stops and how the solve runs.
// Part of the service's interface (service_api.h), so the API's router and the service check it
// the same way.
//
// Error policy: Check() throws ApiError 400 naming the bad setting.
#pragma once

#include <cstddef>
#include <optional>
#include <string>

#include "calib/wand_coverage.h"
#include "calib/wand_observations.h"
#include "calib/wand_quality.h"
#include "geometry/camera.h"

namespace mocap::service {

// "wand": the wand waved (wand_calibration.h); "single-marker": one marker waved, then a bar
// of two markers wand_length_mm apart shown for the scale (single_marker_calibration.h).
inline constexpr const char* kWandingModeWand = "wand";
inline constexpr const char* kWandingModeSingleMarker = "single-marker";

struct WandingOptions {
  std::string session;             // the capture's name in the sessions directory
  std::string mode = kWandingModeWand;
  double wand_length_mm = 0.0;     // between the end markers (single-marker: the scale bar's)
  double middle_marker_mm = 0.0;   // > 0: a third marker this far from the first end
  size_t min_samples = 300;        // wand (single-marker: marker) samples every camera needs
  size_t min_scale_frames = 30;    // single-marker: frame sets showing the scale bar in 2+ cameras
  double coverage_target = 0.4;    // covered share of every camera's image (calibrate wand refuses < 0.2)
  double timeout_s = 300.0;        // collection stops here whatever the coverage
  std::string refine_intrinsics = "none";  // none, focal-principal or all
  std::optional<Rig> intrinsics;   // none: the calibration serve runs with
  WandCoverageOptions coverage;
  RatingThresholds thresholds;

  bool SingleMarker() const { return mode == kWandingModeSingleMarker; }
  WandGeometry Wand() const;  // the wand, or the scale bar (two markers) for a single marker
  void Check() const;
};

}  // namespace mocap::service

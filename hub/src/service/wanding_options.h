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

struct WandingOptions {
  std::string session;             // the capture's name in the sessions directory
  double wand_length_mm = 0.0;     // between the end markers
  double middle_marker_mm = 0.0;   // > 0: a third marker this far from the first end
  size_t min_samples = 300;        // wand samples every camera needs
  double coverage_target = 0.4;    // covered share of every camera's image (calibrate wand refuses < 0.2)
  double timeout_s = 300.0;        // collection stops here whatever the coverage
  std::string refine_intrinsics = "none";  // none, focal-principal or all
  std::optional<Rig> intrinsics;   // none: the calibration serve runs with
  WandCoverageOptions coverage;
  RatingThresholds thresholds;

  WandGeometry Wand() const;
  void Check() const;
};

}  // namespace mocap::service

// Live wanding in `serve`, the collecting part: while the wand is waved (and captured into a
// session), every frame set feeds each camera's wand samples and image coverage
// (calib/wand_coverage.h); collection stops when every camera has enough samples and coverage,
// or at the timeout. Pure: time is passed in, no threads, no files; HubService owns one on its
// loop and hands the recorded session to a WandSolveJob when it stops.
//
// Error policy: WandingOptions::Check() throws ApiError 400 naming the bad setting.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "calib/wand_coverage.h"
#include "calib/wand_observations.h"
#include "calib/wand_quality.h"
#include "geometry/camera.h"
#include "ingest/camera_frame.h"

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

class WandCollection {
 public:
  // Throws ApiError 400 on bad options.
  WandCollection(const Rig& rig, WandingOptions options, uint64_t now_ns);

  void Add(const FrameSet& set) { coverage_.Add(set); }
  // Why collection should stop now ("every camera has enough", "timed out after N s"), or empty.
  std::string StopReason(uint64_t now_ns) const;
  bool EveryCameraHasEnough() const;
  // {"elapsed_s", "timeout_s", "frame_sets", "wand_frames", "min_samples", "coverage_target",
  //  "grid": {"columns", "rows", "cell_samples"},
  //  "cameras": [{"id", "samples", "coverage", "enough", "region", "advice", "counts": [...]}],
  //  "advice": ["camera 4: wave towards the top left (...)", ...] (the cameras still short)}
  nlohmann::json Json(uint64_t now_ns) const;
  const WandingOptions& options() const { return options_; }

 private:
  WandingOptions options_;
  WandCoverage coverage_;
  uint64_t start_ns_;
};

}  // namespace mocap::service

// Live wanding in `serve`, the collecting part: while the wand is waved (and captured into a
// session), every frame set feeds each camera's wand samples and image coverage
// (calib/wand_coverage.h); collection stops when every camera has enough samples and coverage,
// or at the timeout. A single marker (WandingOptions::mode) counts the frames with exactly one
// blob as samples, and the frame sets that show the scale bar (exactly two blobs) in two or more
// cameras, which it needs min_scale_frames of too. Pure: time is passed in, no threads, no files; HubService owns one on its
// loop and hands the recorded session to a WandSolveJob when it stops.
//
// Error policy: the constructor throws ApiError 400 naming the bad setting (WandingOptions::Check,
// wanding_options.h).
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "calib/wand_coverage.h"
#include "geometry/camera.h"
#include "ingest/camera_frame.h"
#include "service/wanding_options.h"

namespace mocap::service {

class WandCollection {
 public:
  // Throws ApiError 400 on bad options.
  WandCollection(const Rig& rig, WandingOptions options, uint64_t now_ns);

  void Add(const FrameSet& set) {
    coverage_.Add(set);
    if (scale_) scale_->Add(set);
  }
  // Why collection should stop now ("every camera has enough", "timed out after N s"), or empty.
  std::string StopReason(uint64_t now_ns) const;
  // Every camera has its samples and coverage (and, for a single marker, the scale bar was seen).
  bool EveryCameraHasEnough() const;
  // {"mode", "elapsed_s", "timeout_s", "frame_sets", "wand_frames", "min_samples", "coverage_target",
  //  "scale_frames", "min_scale_frames" (single marker; null for the wand),
  //  "grid": {"columns", "rows", "cell_samples"},
  //  "cameras": [{"id", "samples", "coverage", "enough", "region", "advice", "counts": [...]}],
  //  "advice": ["camera 4: wave towards the top left (...)", ...] (the cameras still short)}
  nlohmann::json Json(uint64_t now_ns) const;
  const WandingOptions& options() const { return options_; }

 private:
  bool ScaleHasEnough() const;

  WandingOptions options_;
  WandCoverage coverage_;
  std::optional<WandCoverage> scale_;  // single marker: the scale bar's frames
  uint64_t start_ns_;
};

}  // namespace mocap::service

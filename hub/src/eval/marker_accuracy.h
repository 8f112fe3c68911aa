// Reconstruction accuracy against ground truth, with DESIGN.md's metrics: per frame a one-to-one
// minimum-total-distance matching (gated) of output points to the truth markers present, then
// RMSE, ghosts, missing, trajectories, fragmentation and swaps.
#pragma once

#include <cstddef>
#include <string>

#include <nlohmann/json_fwd.hpp>

#include "io/marker_trajectories.h"
#include "io/visibility.h"

namespace mocap {

struct MarkerEvalOptions {
  double gate_mm = 20.0;
  // With visibility, a truth marker only counts as missing when at least this many cameras
  // delivered a blob of it (fewer cannot be triangulated).
  int min_cameras = 2;

  void Check() const;  // throws std::invalid_argument
};

struct MarkerEvalReport {
  size_t frames = 0;                 // truth frames (per-frame figures divide by this)
  size_t result_frames = 0;          // result rows aligned with a truth frame
  size_t unaligned_result_frames = 0;// result rows at times the truth does not have
  size_t truth_markers = 0;          // truth columns that ever hold data
  size_t truth_points = 0;           // present truth marker-frames
  size_t expected_points = 0;        // of those, the ones that count for missing
  size_t result_points = 0;          // output points in aligned frames
  size_t matched = 0;
  double rmse_mm = 0.0;
  double mean_error_mm = 0.0;
  double p95_error_mm = 0.0;
  double max_error_mm = 0.0;
  size_t ghosts = 0;
  double ghosts_per_frame = 0.0;
  size_t missing = 0;
  double missing_per_frame = 0.0;
  size_t trajectories = 0;
  double fragmentation = 0.0;        // trajectories per truth marker
  size_t swaps = 0;
  // Two truth markers that exchange places (eval/truth_exchanges.h), and the swaps counted where
  // the output column's old or new marker is one of an exchanging pair (included in swaps).
  size_t truth_exchanges = 0;
  size_t swaps_at_truth_exchanges = 0;
  bool visibility_used = false;
  double gate_mm = 0.0;
  // Labelling, when the result names some of its columns with the truth's names: an output point
  // is correctly named when its column's name is the name of the truth marker it matched; wrongly
  // named when its column carries a truth name but it matched another marker or none. Shares are
  // of all output points in aligned frames (unnamed points count in neither).
  bool labels_compared = false;
  size_t named_points = 0;
  size_t correctly_named = 0;
  size_t wrongly_named = 0;
  double correct_share = 0.0;
  double wrong_share = 0.0;
  double worst_frame_correct_share = 0.0;  // the lowest share of one frame (frames with points)

  nlohmann::json ToJson() const;
  std::string ToText() const;
};

// `visibility` may be null (then every present truth marker counts for missing). Throws
// std::invalid_argument when the inputs cannot be compared (no rate, visibility names differ).
MarkerEvalReport EvaluateMarkers(const MarkerTrajectories& truth, const MarkerTrajectories& result,
                                 const MarkerVisibility* visibility, const MarkerEvalOptions& options = {});

}  // namespace mocap

// Reconstruction accuracy against ground truth, with DESIGN.md's metrics: per frame a one-to-one
// minimum-total-distance matching (gated) of output points to the truth markers present, then
// RMSE, ghosts, missing, trajectories, fragmentation and swaps; names right, wrong and unnamed, ids
// changed per truth marker and names changed per track.
#pragma once

#include <cstddef>
#include <string>

#include <nlohmann/json_fwd.hpp>

#include "io/live_points.h"
#include "io/marker_trajectories.h"
#include "io/visibility.h"

namespace mocap {

struct MarkerEvalOptions {
  double gate_mm = 20.0;
  // With visibility, a truth marker only counts as missing when at least this many cameras
  // delivered a blob of it (fewer cannot be triangulated).
  int min_cameras = 2;
  // Name shares count a truth marker's points from its Nth frame present on (1: all), so that a
  // live result's first frames of each marker, before a name can be certain, can be set apart.
  int names_from_frame = 1;

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
  // Two truth markers that exchange places (scoring/truth_exchanges.h), and the swaps counted where
  // the output column's old or new marker is one of an exchanging pair (included in swaps).
  size_t truth_exchanges = 0;
  size_t swaps_at_truth_exchanges = 0;
  bool visibility_used = false;
  double gate_mm = 0.0;
  // Identity: times a truth marker's matched track changes (a new trajectory after a gap counts;
  // for a live result, a track's new number on confirmation counts), in all and at most for one
  // marker; times a track's name changes to another name (unnamed frames between do not count),
  // in all, tracks ever renamed and at most for one track. A TRC's column is one track with one
  // name: it never changes name.
  size_t id_changes = 0;
  double id_changes_per_marker = 0.0;
  size_t max_id_changes = 0;
  size_t name_changes = 0;
  size_t tracks_renamed = 0;
  size_t max_name_changes = 0;
  // Labelling, when the result names some of its points with the truth's names: an output point is
  // correctly named when its name is the name of the truth marker it matched; wrongly named when it
  // carries a truth name but matched another marker or none; unnamed otherwise (the hub's anonymous
  // M001... names are unnamed even where the truth's markers are called so). Shares are of the
  // output points in aligned frames (label_points: from each truth marker's names_from_frame on).
  bool labels_compared = false;
  int names_from_frame = 1;
  size_t label_points = 0;
  size_t named_points = 0;
  size_t correctly_named = 0;
  size_t wrongly_named = 0;
  size_t unnamed_points = 0;
  double correct_share = 0.0;
  double wrong_share = 0.0;
  double unnamed_share = 0.0;
  double worst_frame_correct_share = 0.0;  // the lowest share of one frame (frames with points)

  nlohmann::json ToJson() const;
  std::string ToText() const;
};

// `visibility` may be null (then every present truth marker counts for missing). `identity` (a
// live result's, io/live_points.h) gives each point its track and name; null: each result column
// is one track named by its column name. Throws std::invalid_argument when the inputs cannot be
// compared (no rate, visibility names differ, identity not sized to the result).
MarkerEvalReport EvaluateMarkers(const MarkerTrajectories& truth, const MarkerTrajectories& result,
                                 const MarkerVisibility* visibility, const MarkerEvalOptions& options = {},
                                 const PublishedIdentity* identity = nullptr);

}  // namespace mocap

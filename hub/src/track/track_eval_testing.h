// Test helper: a tracker run's output rows and its truth as eval's inputs, scored by eval's own
// matching (EvaluateMarkers: one-to-one, minimum total distance, gated), so the track tests and
// `mocap-hub eval` count ghosts, misses and swaps the same way.
#pragma once

#include <algorithm>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "scoring/marker_accuracy.h"
#include "io/marker_trajectories.h"
#include "io/visibility.h"
#include "track/tracker.h"

namespace mocap::testing {

// truth[f][m]: marker m at frame f (a NaN point: absent). views[f][m], when not empty: the cameras
// that saw it (a marker seen by fewer than two cannot count as missing). Frames before
// first_frame are left out (the tracker's start-up).
inline MarkerEvalReport EvaluateTrackRows(const std::map<uint64_t, std::vector<TrackSample>>& rows,
                                          const std::vector<std::vector<Eigen::Vector3d>>& truth, double rate_hz,
                                          size_t first_frame, const std::vector<std::vector<int>>& views = {}) {
  const size_t markers = truth.empty() ? 0 : truth.front().size();
  size_t columns = 0;
  for (const auto& [frame, row] : rows) {
    for (const TrackSample& sample : row) columns = std::max(columns, static_cast<size_t>(sample.marker) + 1);
  }
  MarkerTrajectories expected, result;
  MarkerVisibility visibility;
  expected.rate_hz = result.rate_hz = rate_hz;
  for (size_t m = 0; m < markers; ++m) expected.names.push_back("truth" + std::to_string(m));
  for (size_t c = 0; c < columns; ++c) result.names.push_back(DefaultMarkerName(c));
  visibility.names = expected.names;
  for (size_t f = first_frame; f < truth.size(); ++f) {
    const size_t at = expected.AddFrame(f);
    for (size_t m = 0; m < markers; ++m) expected.At(at, m) = truth[f][m];
    result.AddFrame(f);
    const auto row = rows.find(f);
    if (row != rows.end()) {
      for (const TrackSample& sample : row->second) result.At(at, sample.marker) = sample.position;
    }
    visibility.frame_numbers.push_back(f);
    for (size_t m = 0; m < markers; ++m) {
      visibility.counts.push_back(static_cast<uint16_t>(views.empty() ? 2 : views[f][m]));
    }
  }
  return EvaluateMarkers(expected, result, &visibility);
}

}  // namespace mocap::testing

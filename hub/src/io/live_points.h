// What `serve` published, frame by frame, as a capture keeps it (SESSION/live_points.tsv), so the
// live result itself can be judged by `eval`, not only the TRC made afterwards:
//   # mocap live points v1 rate_hz=240
//   frame  x  y  z  id  provisional  views  rms_px        (tab-separated, mm)
// id: a confirmed marker's number (provisional 0), a tentative track's serial (provisional 1),
// or -1 for a point no track took. Errors: std::runtime_error "<file>:<line>: <why>".
#pragma once

#include <cstdint>
#include <istream>
#include <string>

#include "io/marker_trajectories.h"

namespace mocap {

std::string LivePointsHeader(double rate_hz);
// One line, newline included.
std::string LivePointLine(uint64_t frame, double x, double y, double z, long long id, bool provisional, int views,
                          double rms_px);

// The published points as trajectories: each confirmed marker its own column ("M001" for id 0);
// provisional and untracked points in a pool of columns ("P1", "P2", ...) reused once their track
// is gone, so memory follows the points present at once, not the number of tracks ever tried.
MarkerTrajectories ReadLivePoints(const std::string& path);
// The same from a stream; `path` names it in errors.
MarkerTrajectories ParseLivePoints(std::istream& in, const std::string& path);

}  // namespace mocap

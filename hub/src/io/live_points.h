// What `serve` published, frame by frame, as a capture keeps it (SESSION/live_points.tsv), so the
// live result itself can be judged by `eval`, not only the TRC made afterwards:
//   # mocap live points v1 rate_hz=240
//   frame  x  y  z  id  provisional  views  rms_px  [name]      (tab-separated, mm)
// id: a confirmed marker's number (provisional 0), a tentative track's serial (provisional 1),
// or -1 for a point no track took. name: the marker set's name published on the point (serve
// --labels); absent when unnamed (files written before names were kept have none).
// Errors: std::runtime_error "<file>:<line>: <why>".
#pragma once

#include <cstdint>
#include <istream>
#include <string>
#include <vector>

#include "io/marker_trajectories.h"

namespace mocap {

// Who each point of a result is where a column is not one track with one name all along (what
// serve published live): per cell of the trajectories (frame-major), the track that published it
// and the name it carried.
struct PublishedIdentity {
  std::vector<std::string> names;  // every name published, once each
  std::vector<int64_t> track;      // per cell; -1: a gap, or a point no track took
  std::vector<int32_t> name;       // per cell: index into names; -1: unnamed or a gap
};

struct LivePoints {
  // Each confirmed marker its own column ("M001" for id 0); provisional and untracked points in a
  // pool of columns ("P1", "P2", ...) reused once their track is gone, so memory follows the
  // points present at once, not the number of tracks ever tried.
  MarkerTrajectories points;
  // Tracks: confirmed marker m is 2m, tentative serial s is 2s + 1 (the file numbers them apart,
  // so a client sees a track's confirmation as a change of id, and so does eval).
  PublishedIdentity identity;
};

std::string LivePointsHeader(double rate_hz);
// One line, newline included; `name` empty: unnamed. Throws std::invalid_argument for a name
// with a tab, a line break or a control character (it would break the row).
std::string LivePointLine(uint64_t frame, double x, double y, double z, long long id, bool provisional, int views,
                          double rms_px, const std::string& name = {});

LivePoints ReadLivePoints(const std::string& path);
// The same from a stream; `path` names it in errors.
LivePoints ParseLivePoints(std::istream& in, const std::string& path);

}  // namespace mocap

// Frames where two truth markers exchange places. Reference trajectories come from labelled
// recordings, and a labelling mistake (or cluster markers built on a segment frame that flips)
// makes two close markers trade names, for a frame or for good: both labelled paths then jump by
// the markers' distance while the paths traded are smooth. Markers do not jump; a tracker that
// follows them is counted a swap against such a truth at every exchange. eval reports the
// exchanges and the swaps at them beside the swap count, which still counts every swap.
#pragma once

#include <cstddef>
#include <vector>

#include "io/marker_trajectories.h"

namespace mocap {

struct TruthExchangeOptions {
  // Pairs of markers closer than this in the frame before the boundary are judged.
  double radius_mm = 60.0;
  // An exchange: the paths traded from the boundary on are at most `ratio` as rough as the
  // labelled paths across it (JoinRoughness of both markers), and smoother by at least
  // min_jump_mm squared.
  double ratio = 0.5;
  double min_jump_mm = 6.0;
};

struct TruthExchanges {
  size_t count = 0;  // (boundary, pair) exchanges found
  // For each truth frame index, the markers that exchange places with another at the boundary
  // before that frame.
  std::vector<std::vector<size_t>> markers_at_frame;

  bool Involves(size_t frame_index, size_t marker) const;
};

// Boundaries need the truth frames two before and one after them, consecutive in frame number.
TruthExchanges FindTruthExchanges(const MarkerTrajectories& truth, const TruthExchangeOptions& options = {});

}  // namespace mocap

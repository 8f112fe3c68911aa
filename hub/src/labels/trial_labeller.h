// Labelling a whole recording (reconstruct --labels, labels apply): the frame-by-frame labeller
// (marker_labeller.h) runs over every frame with each column's unbroken runs of frames as its
// tracks (a run ends at a gap, and where the swap guard took a name back), then each run gets one
// name for its whole life: the name with most support (frames it held the name, plus the mean
// shape's votes), when that is at least half of its support and no run overlapping it in time
// holds the same name with more support. The runs' names are then refined as a whole by their
// distances (local search on the assignment: the long runs' names solved together, then
// exchanges, which may leave two runs sharing a name for up to 5 frames at their ends, and
// moves, the longer runs first); inside a cluster of three or more markers the frame built on its neighbouring segments
// (segment_frames.h) decides what the distances cannot; names two runs could exchange at almost
// no cost are dropped unless that frame confirms them (they cannot be told apart), and so is a
// name whose distances fit worse than none. A run that breaks its steady distances, or whose name
// another point of the frame would carry far better, for 5 frames or more is split there (the
// tracker swapped it; a run left unnamed is checked with the name its frames supported) and the
// pieces named again the same way. Last, frame by frame, a named point that breaks most of its
// steady distances (on another subject: the subject's own) loses its name for that frame (a swap
// inside a run), and so do two points holding one name. A run or point without a name keeps its
// column's anonymous name, so the output holds one column per name placed (in the set's order)
// and then the leftovers. Pure.
#pragma once

#include <cstddef>

#include "io/marker_trajectories.h"
#include "labels/marker_labeller.h"
#include "labels/marker_set.h"

namespace mocap {

struct TrialLabelling {
  MarkerTrajectories named;
  size_t runs = 0;          // unbroken runs of the input's columns (split where they broke)
  size_t named_runs = 0;    // of those, the ones given a name
  size_t names_placed = 0;  // marker-set names that hold data
  size_t named_points = 0, points = 0;
  size_t frame_names_dropped = 0;  // points of named runs left unnamed in a frame that broke the distances
  LabellerStats stats;
};

// Throws std::invalid_argument for bad options or a marker set that cannot label.
TrialLabelling LabelTrajectories(const MarkerTrajectories& anonymous, const MarkerSet& set,
                                 const LabellerOptions& options = {});

}  // namespace mocap

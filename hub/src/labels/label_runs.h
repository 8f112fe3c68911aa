// The pieces the offline labeller names: runs (a column's stretch of frames that one name may
// take) and the distance statistics of two runs, with their cost against a marker set.
#pragma once
#include <cstddef>
#include <map>

#include "labels/marker_set.h"

namespace mocap {

struct Run {
  size_t column = 0;
  size_t first = 0, last = 0;  // frame indices, inclusive
  std::map<int, double> support;
  double total = 0.0;
  int label = -1;
  int candidate = -1;  // the name its frames supported (kept when the refinement leaves it unnamed)
};

// Distance statistics of two runs over the frames they share.
struct RunPair {
  double mean = 0.0, sd = 0.0;
  int frames = 0;
};

// How far two runs' distance is from what the set says of their names: in units of the spread
// the set and the runs allow (plus `relative` of the distance: another subject's markers sit
// elsewhere), squared and capped so that one odd pair cannot outweigh the rest.
double PairCost(const MarkerSet& set, int a, int b, const RunPair& pair, double relative);

}  // namespace mocap

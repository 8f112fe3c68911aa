// Gap filling on a take under edit, one marker at a time, by five methods (docs/editor.md has
// their measured accuracy):
//   spline     a natural cubic spline through `context` measured samples on each side of the
//              gap, spaced a fifth of the gap's length apart (at least one frame), in the spirit
//              of Woltring's spline fill (interpolating, not smoothing); needs both sides;
//   linear     a straight line between the two samples bounding the gap;
//   pattern    the donor marker's path, shifted by the target-donor offset at the gap's ends
//              (blended linearly from one end to the other);
//   rigid      three or more donors on the same segment: their motion from each end of the gap
//              (a least-squares rigid transform, Kabsch/Umeyama without scale) carries the
//              target's position at that end; the two estimates are blended across the gap;
//   relational the target's coordinates in a frame built from three donors (origin, axis, plane:
//              works when the donors are not a rigid cluster), blended the same way.
// The donor methods fill with one end known too (the estimate from that end alone); a frame where
// a donor is missing stays a gap. Filled samples carry the method in EditedTake::marks.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "edit/edited_take.h"

namespace mocap::edit {

struct FillOptions {
  FillMethod method = FillMethod::kSpline;
  std::vector<size_t> donors;  // columns: pattern 1, rigid 3 or more, relational 3
  // Measured samples used on each side of a gap (spline only), 2-1000.
  int context = 10;
  // Gaps longer than this many frames are left alone (0: any length).
  int max_gap = 0;

  // std::invalid_argument naming the field, value and rule.
  void Check() const;
};

struct FillResult {
  size_t gaps_seen = 0;       // gaps (runs of missing frames) inside the range
  size_t gaps_filled = 0;     // of which every frame was filled
  size_t samples_filled = 0;
  size_t samples_left = 0;    // frames of those gaps still missing (edges, donors missing, too long)
};

// Fills the gaps of column `marker` within frame indices [first, last] (inclusive). A gap that
// starts before `first` or ends after `last` counts as inside when it overlaps the range, and is
// filled whole: a fill needs the samples that bound it.
FillResult FillGaps(EditedTake* take, size_t marker, size_t first, size_t last, const FillOptions& options);

}  // namespace mocap::edit

// The marker set placed on one frame of anonymous points with no history: how a subject is
// initialised (as Vicon's auto-initialise and QTM's AIM place their model on the first frames in
// which it is seen whole). The set's mean shape is fitted upright (a turn about +z, the subject's
// scale and a shift, searched from several headings, the best placed 60 % of the points deciding:
// swinging limbs do not turn the body), then each segment of three or more markers is fitted
// rigidly onto its points (a proper rotation, so a segment's mirror image fits worse than the
// segment: handedness), smaller segments are shifted, and the points are matched to the placed
// markers one to one. A point is named only when it is near its placed marker and no other point
// or marker comes close (a wrong name is worse than none). Pure.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "labels/marker_set.h"

namespace mocap {

struct SetFitOptions {
  double gate_mm = 60.0;          // a point farther than this from its placed marker is not named
  double search_gate_mm = 300.0;  // while the body's placement is searched for
  double ambiguity_ratio = 1.8;   // the next nearest point (or marker) at least this much farther...
  double margin_mm = 15.0;        // ...and at least this much
  int headings = 12;              // turns about the vertical tried
  int segment_rounds = 3;         // rounds of segment fits and matching
  void Check() const;             // throws std::invalid_argument naming the field
};

struct SetFit {
  std::vector<int> labels;  // per point: the set's marker index, or -1
  double scale = 1.0;       // the subject's size over the set's
  double score = 0.0;       // mean squared distance of the best placed 60 %, mm^2 (lower: better)
};

// `points_z_up`: one frame in the set's frame (+z up; finite points only). `known` (optional, per
// point a marker index or -1): names already given; with four or more the body is placed on them
// instead of searched for (a subject already initialised), and only the other points and markers
// are matched (the known points keep their names in the result). Throws std::invalid_argument for bad
// options, `known` not one per point, or a set with fewer than 3 markers in its mean shape.
SetFit FitSetToFrame(const MarkerSet& set, const std::vector<Eigen::Vector3d>& points_z_up,
                     const SetFitOptions& options = {}, const std::vector<int>* known = nullptr);

}  // namespace mocap

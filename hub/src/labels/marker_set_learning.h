// Learning a marker set from labelled trials (`labels learn`): the names (every named column of
// the trials, in first-seen order), the mean body shape (every frame turned about the vertical
// and moved onto a reference frame, then averaged: generalised Procrustes without tilt, so the
// shape stays upright), the distance statistics of every pair seen together, and the segments:
// clusters in which every pair's distance varies by at most `rigid_sd_mm` (complete linkage, so
// a chain of near-rigid pairs does not glue a whole limb together).
// Errors: std::invalid_argument naming the trial and the problem. Pure.
#pragma once

#include <string>
#include <vector>

#include "io/marker_trajectories.h"
#include "labels/marker_set.h"

namespace mocap {

struct MarkerSetLearnOptions {
  double rigid_sd_mm = 5.0;          // a pair this steady belongs to one segment
  double max_segment_mm = 500.0;     // nor are markers farther apart than this
  size_t min_pair_frames = 10;       // fewer frames together: no distance statistics
  // Vertical axis of the trials (0 x, 1 y, 2 z, positive up); -1 detects it per trial.
  int up_axis = -1;
  void Check() const;  // throws std::invalid_argument
};

// `sources` name the trials in errors (same order). Trials need names that are not the hub's
// anonymous M001... (a reconstruction without labels teaches nothing).
MarkerSet LearnMarkerSet(const std::vector<MarkerTrajectories>& trials, const std::vector<std::string>& sources,
                         const MarkerSetLearnOptions& options = {});

// The rotation (a signed permutation of the axes, determinant +1) taking a frame with the given
// up axis to the marker set's frame, where +z is up.
Eigen::Matrix3d UpToZ(int up_axis);

}  // namespace mocap

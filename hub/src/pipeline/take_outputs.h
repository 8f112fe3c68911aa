// A finished take's markers → names from a marker set → rigid bodies' poses and one virtual marker
// per body: the whole-take steps after OfflineReconstruction (offline_reconstruction.h), which
// `reconstruct --labels/--bodies` runs and `labels apply` (names alone). They need the whole take:
// a name attaches to a whole track run (labels/trial_labeller.h) and a body's orientation is
// refitted over the frames around it (bodies/body_smoothing.h). No files: the caller reads the
// marker set and the bodies and writes what comes out.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "bodies/body_smoothing.h"
#include "bodies/body_trajectories.h"
#include "bodies/body_definition.h"
#include "io/marker_trajectories.h"
#include "labels/marker_set.h"

namespace mocap::pipeline {

// What naming did, as `reconstruct` and `labels apply` print it.
struct TakeNaming {
  size_t names_placed = 0, set_markers = 0;
  size_t named_points = 0, points = 0;
  size_t named_runs = 0, runs = 0;
  size_t frame_names_dropped = 0;
  std::string Describe() const;
};

// Names the take's columns in place from `set` (columns it cannot place keep their names).
// up_axis 0-2, or -1 to detect it from the markers. Throws std::invalid_argument when the set
// cannot label (labels/trial_labeller.h).
TakeNaming NameTake(const MarkerSet& set, int up_axis, MarkerTrajectories* markers);

// The bodies' poses over the take (one row per frame) and what the smoothing did per body.
struct TakeBodies {
  std::vector<BodyPoseRow> rows;
  std::vector<BodySmoothingStats> smoothing;
  size_t FramesFitted(size_t body) const;
};

// Fits every body over the take and appends one column per body named after it (its pivot, a gap
// where not fitted).
TakeBodies FitTakeBodies(const std::vector<RigidBodyDefinition>& bodies, const BodySmoothingOptions& smoothing,
                         MarkerTrajectories* markers);

}  // namespace mocap::pipeline

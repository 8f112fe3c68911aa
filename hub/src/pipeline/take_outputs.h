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

// Which whole-take labeller names: the frame-by-frame pass refined by distances
// (labels/trial_labeller.h, the default) or a subject model initialised on the take itself
// (labels/subject_labeller.h: no wrong name where it can leave one unnamed, but below the default
// on some takes; docs/labels.md).
enum class TakeLabeller { kTrial, kSubject };

// What naming did, as `reconstruct` and `labels apply` print it.
struct TakeNaming {
  TakeLabeller labeller = TakeLabeller::kTrial;
  size_t names_placed = 0, set_markers = 0;
  size_t named_points = 0, points = 0;
  size_t named_runs = 0, runs = 0;
  size_t frame_names_dropped = 0;
  // The subject model's alone: its initialisation (first frame index, -1: none; names given) and
  // every decision it made (`decisions` holds the first ones, one line each).
  long init_frame = -1;
  size_t init_names = 0;
  size_t decisions_made = 0;
  std::vector<std::string> decisions;
  std::string Describe() const;
};

// Names the take's columns in place from `set` (columns it cannot place keep their names).
// up_axis 0-2, or -1 to detect it from the markers. Throws std::invalid_argument when the set
// cannot label (labels/trial_labeller.h, labels/subject_labeller.h).
TakeNaming NameTake(const MarkerSet& set, int up_axis, MarkerTrajectories* markers,
                    TakeLabeller labeller = TakeLabeller::kTrial);

// The bodies' poses over the take (one row per frame) and what the smoothing did per body.
struct TakeBodies {
  std::vector<BodyPoseRow> rows;
  std::vector<BodySmoothingStats> smoothing;
  size_t FramesFitted(size_t body) const;
  // Why `body` was not fitted where it was not, by cause with its frame count ("412 frames: no
  // three points with the sides of its triangles; 3 frames: ..."), most frequent first; empty
  // when it was fitted in every frame.
  std::string MissSummary(size_t body) const;
};

// Fits every body over the take and appends one column per body named after it (its pivot, a gap
// where not fitted).
TakeBodies FitTakeBodies(const std::vector<RigidBodyDefinition>& bodies, const BodySmoothingOptions& smoothing,
                         MarkerTrajectories* markers);

}  // namespace mocap::pipeline

// Offline refinement of a rigid body's orientation over neighbouring frames (reconstruct
// --bodies). One frame's fit is already as good as its points allow: for bodies of 4-6 markers
// within 120 mm seen by 8 cameras at 0.2 px, the rotation's Cramer-Rao bound from that frame's
// blobs is 0.22-0.30 deg median, and a fit to the 2D rays instead of the triangulated points
// reaches the same (docs/rigid-bodies.md). Only more frames can do better, and offline they may
// come from both sides, so there is no lag:
// - the orientation at frame f is refitted to the per-frame orientations of frames f-k..f+k
//   under a steady angular acceleration (a parabola in the rotation's tangent space at frame f;
//   a straight line, steady angular velocity, is biased where the spin axis wanders), each frame
//   weighted by its fit's information (its markers' spread about their centroid, over the point
//   noise estimated from all of the body's fit residuals);
// - the window shrinks, down to the frame alone, while its frames disagree with that model by
//   more than their noise (chi-square test): a sudden turn or a knock stays as measured;
// - the position keeps the frame's measured marker centroid (x = centroid - R' * body centroid).
// Frames not fitted (predicted or lost) are left alone. The window fit and its test are
// body_rotation_window.h's, shared with the live estimator (body_live_filter.h), which sees
// past frames only. Pure: no I/O, single-threaded.
// Errors: std::invalid_argument for bad options.
#pragma once

#include <cstddef>
#include <vector>

#include <Eigen/Core>

#include "bodies/body_definition.h"
#include "bodies/body_rotation_window.h"
#include "bodies/body_tracker.h"

namespace mocap {

struct BodySmoothingOptions {
  int half_window = 6;   // frames each side; 0 leaves the per-frame poses as they are
  int degree = 2;        // of the rotation vector's polynomial in time (2: steady angular acceleration)
  double test_z = 3.09;  // the test's one-sided normal quantile (3.09: a model this wrong 1 in 1000)
  void Check() const;    // throws std::invalid_argument
};

struct BodySmoothingStats {
  size_t refined = 0;     // frames refitted over the full window
  size_t shrunk = 0;      // over a smaller window: the frames around disagreed with the model
  size_t unchanged = 0;   // fitted frames left as they were (no window passed, or too few frames)
  double noise_mm = 0.0;  // the point noise per axis estimated from the fit residuals
};

// Refines `poses` (one body, consecutive frames; `markers` the same length) in place: the
// orientation, position, pivot and mean marker error of every tracked frame.
BodySmoothingStats SmoothBodyPoses(const RigidBodyDefinition& body, const std::vector<BodyFrameMarkers>& markers,
                                   std::vector<BodyPose>* poses, const BodySmoothingOptions& options = {});

}  // namespace mocap

// Live rigid-body poses (serve --bodies; reconstruct --bodies-live measures the same path over a
// session): the tracker's per-frame fits (body_tracker.h), then each frame's orientation refined
// from that frame and the past ones only, so that the pose of frame N is published with frame N.
// One frame's blobs bound its rotation at 0.22-0.30 deg median for bodies of 4-6 markers within
// 120 mm (docs/rigid-bodies.md); the past frames bring that down the way the offline
// refinement (body_smoothing.h) does from both sides, with the same pieces
// (body_rotation_window.h):
// - the orientation at frame N is the value at t = 0 of a polynomial in time fitted to the
//   per-frame orientations of frames N-k..N (a parabola by default: steady angular acceleration;
//   a straight line extrapolated to the window's end is biased by the spin axis wandering),
//   each frame weighted by its fit's information over the point noise;
// - the window grows from a few frames while its frames agree with that model within their
//   noise (the same chi-square test as offline: the onset of a fast turn or a knock stops it, so
//   that it is followed at once rather than averaged with the frames before it) and while its
//   value at t = 0 agrees with every smaller window's within that one's uncertainty (the
//   intersection-of-confidence-intervals rule): read at its end, a window's model error is
//   largest where its residuals do not show it, and a longer window that moves the estimate by
//   more than the shorter ones' noise is biased by more than it gains; frame N alone when none
//   passes;
// - the point noise is estimated from how each marker's fit residual changes between
//   consecutive frames, over every frame so far (nothing is refined until a few frames' worth
//   have been seen): a marker whose defined place is off by a constant inflates its residuals
//   (3x for one body rendered by `sim render`), and a noise estimate that large let biased
//   windows pass the tests;
// - the position keeps the frame's measured marker centroid; predicted and lost frames are the
//   tracker's.
// Single-threaded; memory bounded by the window. Errors: std::invalid_argument for bad options.
#pragma once

#include <cstdint>
#include <deque>
#include <vector>

#include <Eigen/Core>

#include "bodies/body_rotation_window.h"
#include "bodies/body_tracker.h"

namespace mocap {

struct BodyLiveFilterOptions {
  int past_frames = 30;  // the window: this frame and up to this many before it; 0: each frame alone
  int degree = 2;        // of the rotation vector's polynomial in time
  double test_z = 3.09;  // the test's one-sided normal quantile (as the offline refinement's)
  double agreement_z = 2.33;  // windows' agreement at t = 0: one-sided normal quantile of its chi-square
  void Check() const;    // throws std::invalid_argument
};

struct BodyLiveFilterStats {
  size_t refined = 0;     // frames refitted over the full window
  size_t shrunk = 0;      // over a shorter one: the longer ones disagreed with the model or the shorter
  size_t unchanged = 0;   // fitted frames published as fitted (no window passed, or too little history)
  double noise_mm = 0.0;  // the point noise per axis estimated so far
};

class BodyLiveFilter {
 public:
  // Throws std::invalid_argument for bad options.
  BodyLiveFilter(std::vector<RigidBodyDefinition> bodies, const BodyLiveFilterOptions& options = {});

  // One frame: `poses` (one per body, as BodyTracker::Update returned them for `points`) refined
  // in place. Frame numbers must increase; a frame number that does not restarts the history.
  void Update(uint64_t frame_number, const std::vector<Eigen::Vector3d>& points, std::vector<BodyPose>* poses);

  BodyLiveFilterStats stats(size_t body) const;

 private:
  struct PastFit {
    uint64_t frame = 0;
    BodyFrameFit fit;
  };
  struct State {
    std::deque<PastFit> past;  // usable fits of the last past_frames frames, oldest first
    // The point noise from the change of each marker's residual (body frame) between consecutive
    // fitted frames: a marker whose place in the definition is off by a constant (a definition
    // from another capture, a rendered blob's bias) adds to its residual but not to that change,
    // and only what changes from frame to frame is noise a window averages.
    double change_sq = 0.0, change_dof = 0.0;
    uint64_t residual_frame = 0;                    // the frame of `residuals`
    std::vector<Eigen::Vector3d> residuals;         // per body marker
    std::vector<char> has_residual;                 // per body marker

    BodyLiveFilterStats stats;
  };
  void Refine(size_t body, uint64_t frame_number, const BodyFrameMarkers& markers, BodyPose* pose);
  void TrackResidualChanges(size_t body, uint64_t frame_number, const std::vector<Eigen::Vector3d>& points,
                            const BodyPose& pose);
  // Whether `curve` (the window |t| <= k of samples_) reads the same at t = 0 as a polynomial
  // one degree higher through the same frames, within their difference's noise.
  bool EndAgreesWithHigherDegree(const RotationCurveFit& curve, int k, double variance) const;

  std::vector<RigidBodyDefinition> bodies_;
  BodyLiveFilterOptions options_;
  std::vector<State> states_;
  bool started_ = false;
  uint64_t last_frame_ = 0;
  BodyFrameMarkers markers_;            // scratch
  std::vector<RotationSample> samples_;  // scratch
  double agreement_limit_ = 0.0;
};

// The live path as one object: the tracker, then the filter (serve and reconstruct --bodies-live).
class LiveBodyTracker {
 public:
  LiveBodyTracker(std::vector<RigidBodyDefinition> bodies, const BodyTrackerOptions& tracker = {},
                  const BodyLiveFilterOptions& filter = {});
  // One frame's points (any order); frame numbers increasing. One pose per body.
  const std::vector<BodyPose>& Update(uint64_t frame_number, const std::vector<Eigen::Vector3d>& points);
  const std::vector<RigidBodyDefinition>& bodies() const { return tracker_.bodies(); }
  const BodyLiveFilter& filter() const { return filter_; }

 private:
  BodyTracker tracker_;
  BodyLiveFilter filter_;
  std::vector<BodyPose> poses_;
};

}  // namespace mocap

// Tunable settings of the tracking layer, options structs with defaults and Check().
// Error policy of track: Check() throws std::invalid_argument naming the bad field; processing
// never throws on data (points that fit no track start tentative tracks or are dropped).
#pragma once

#include <string>

namespace mocap {

struct KalmanOptions {
  // White-noise acceleration (mm/s^2, one sigma): human limbs reach a few g.
  double acceleration_noise = 30000.0;
  double measurement_noise_mm = 0.5;
  double initial_velocity_std = 3000.0;  // mm/s, for a track born without a velocity

  void Check() const;
};

enum class AssignmentMethod { kGreedy, kOptimal };
// "greedy" | "optimal"; FromString throws std::invalid_argument on others.
std::string AssignmentMethodToString(AssignmentMethod method);
AssignmentMethod AssignmentMethodFromString(const std::string& name);

struct RigidModelOptions {
  // Pairs farther apart than this at first sight are never linked (different body parts).
  double max_link_distance_mm = 600.0;
  // Seed 001 section 5.1: a link breaks when a distance strays this far from its mean ...
  double max_deviation_mm = 15.0;
  // ... or when the distances' standard deviation grows past this.
  double max_std_mm = 6.0;
  // Samples before a link is trusted for predicting a missing marker.
  int min_samples = 20;
  // Links (longest-lived, steadiest first) used for one prediction.
  int max_links_used = 4;
  // Fewer links than this and no prediction is made.
  int min_links_used = 2;

  void Check() const;
};

struct RigidSwapOptions {
  bool enabled = true;
  // A link counts when it is steady: this many samples and a distance spread within this.
  int min_samples = 20;
  double link_std_mm = 2.0;
  // Tracks steadily linked closer than this form a cluster whose points may be permuted; only
  // clusters of at most max_cluster tracks are searched (max_cluster! permutations).
  double cluster_radius_mm = 60.0;
  int max_cluster = 4;
  // The points are permuted when the chosen assignment misses the cluster's steady distances by
  // more than this (rms, mm) and another permutation's squared misses are below `improvement`
  // times the chosen one's.
  double min_error_mm = 3.0;
  double improvement = 0.25;
  // When no order of its own points fits, a cluster of three or more is gathered again from the
  // points around it (clusters that traded markers).
  bool regather = true;

  void Check() const;
};

// Hindsight swap repair of the offline output (track/hindsight_swaps.h).
struct HindsightSwapOptions {
  bool enabled = true;
  // Pairs of markers closer than this (mm, in the frame before the judged boundary) are judged.
  double pair_radius_mm = 60.0;
  // A trade is undone when it leaves at most `improvement` times the pair's squared
  // accelerations (mm per frame squared, summed over the judged frames) and removes at least
  // min_jump_mm squared: noise never triggers it.
  double improvement = 0.25;
  double min_jump_mm = 6.0;
  // Steady distances (standard deviation at most rigid_max_sd_mm over 10 frames, deviations
  // within max(rigid_tolerance_mm, 4 sd) are noise) are judged with squared excesses weighted by
  // rigid_weight against the squared accelerations: a few mm of bending outweighs any jump.
  double rigid_max_sd_mm = 1.5;
  double rigid_tolerance_mm = 4.0;
  double rigid_weight = 1000.0;

  void Check() const;
};

struct TrackerOptions {
  double rate_hz = 100.0;
  KalmanOptions kalman;
  AssignmentMethod assignment = AssignmentMethod::kOptimal;
  // Gate around a prediction: this many innovation sigmas, clamped to [min, max] mm.
  double gate_sigmas = 5.0;
  double min_gate_mm = 10.0;
  double max_gate_mm = 120.0;
  // A new track is output once it has been measured in this many consecutive frames, each
  // time with at least birth_min_views views; when any of those points had two views only (a
  // ghost of two crossing rays makes one in every frame its blobs last), in
  // two_view_birth_frames: the candidate must persist and keep within its gate of a
  // constant-velocity path, as a marker moves and two unrelated rays' crossing does not.
  int birth_frames = 3;
  int birth_min_views = 2;
  int two_view_birth_frames = 6;
  // A confirmed track without measurement continues on rigid-model predictions for at most
  // this long (s) and coasts on its Kalman prediction (not output) for at most coast_s before
  // it is lost; a lost track can be re-acquired within reacquire_s by a new point near its
  // predicted (or last) position.
  double max_predicted_s = 1.0;
  double coast_s = 0.1;
  double reacquire_s = 3.0;
  double reacquire_gate_mm = 50.0;
  // A drop-out: frames in which no confirmed track is measured (every camera lost, too few left
  // to triangulate, or no frame set at all). Up to this long (s) of them do not count toward
  // coast_s: the tracks are held on their predictions and found again there (the whole search,
  // wide gate included), not lost and renumbered.
  double dropout_hold_s = 0.3;
  // Seed 001 section 5.2's second, global search: predictions and points left unpaired by the
  // gated step are paired again (optimal assignment) within this wider radius, around the rigid
  // model's position when it has one. Catches markers that accelerate hard (a serve's hand).
  double wide_gate_mm = 250.0;
  RigidModelOptions rigid;
  RigidSwapOptions swaps;

  void Check() const;
};

struct GapFillOptions {
  // Gaps up to this many frames between two measured samples become a cubic Hermite spline
  // (callers scale it with the rate: a spline over a fast limb's quarter second overshoots).
  int max_spline_gap = 12;
  // Frames held back before output: bounds both memory and the longest gap filled in place.
  int window_frames = 64;

  void Check() const;
};

}  // namespace mocap

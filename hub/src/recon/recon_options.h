// Tunable settings of the reconstruction layer, each an options struct with defaults and Check().
// Error policy of recon: Check() throws std::invalid_argument naming the bad field (a programming
// or CLI input error); processing never throws on data and returns what it could reconstruct.
#pragma once

#include <string>

namespace mocap {

struct TriangulationOptions {
  int min_views = 2;
  // A view whose refined reprojection error exceeds this is an outlier (merged blob, wrong
  // match); with three or more views the worst one is dropped and the point re-solved.
  double max_reprojection_px = 1.5;
  // With four or more views, the worst view is also dropped when its error exceeds
  // outlier_floor_px and, against the point the other views make without it, outlier_ratio times
  // their median error: a blob biased by a coincident marker's spot, which the absolute limit
  // keeps on a precise rig. The ratio lets Gaussian noise pass (a good view's error there stays
  // under about three times the median), so noisy cameras are judged by the limit above alone.
  double outlier_floor_px = 0.3;
  double outlier_ratio = 8.0;
  // Both relative tests (the view standing out above, a blob two predictions share) apply only
  // to points whose other views agree to this fraction of max_reprojection_px: on noisier
  // cameras the limit alone judges.
  double precise_fraction = 0.1;
  // A view from a blob flagged merged is left out of the solve when min_views other views
  // remain, and stays one of the point's views when its residual is within this (its centroid
  // lies between its markers, up to about a marker radius from each). Never below
  // max_reprojection_px (MergedLimitPx): a merged blob is held to no tighter limit than others.
  double max_merged_px = 4.0;
  int refine_iterations = 4;
  // Points must lie at least this far in front of every camera that sees them.
  double min_depth_mm = 50.0;
  // A matcher's point of two views only (min_views 2) is accepted when at most this many other
  // cameras have it in their image: a marker amid a large rig that only two cameras see is far
  // less likely than two rays of other markers' blobs crossing there. On two to four cameras
  // (seed 000's pair, seed 001's four with a view in four hidden) it always passes.
  int two_view_max_unseen = 2;

  double MergedLimitPx() const { return max_merged_px > max_reprojection_px ? max_merged_px : max_reprojection_px; }
  void Check() const;
};

struct EpipolarGraphOptions {
  // Two blobs of different cameras are linked when their rays pass closer than this.
  double max_ray_distance_mm = 8.0;
  // Ray closest points nearer to a camera than this are behind/at it: not a marker.
  double min_depth_mm = 50.0;

  void Check() const;
};

struct RelaxationOptions {
  int max_iterations = 60;
  // Stop when no label probability changes by more than this in one iteration.
  double tolerance = 1e-4;

  void Check() const;
};

struct ClusteringOptions {
  // Seed 000: rays whose closest points are nearer than this belong to one marker (mm).
  double max_ray_distance_mm = 30.0;

  void Check() const;
};

struct PredictionMatchOptions {
  // Search radius around a prediction reprojected into an image, in pixels: at least this, and
  // more when the predicted point is uncertain (its 3D gate projected at its depth).
  double min_gate_px = 3.0;
  double max_gate_px = 40.0;
  // The point triangulated from the gathered blobs must land this close to the prediction,
  // relative to the prediction's own 3D gate.
  double max_shift_factor = 1.5;
  // Contested predictions are not served: two predictions whose centres are nearer than this
  // factor times the sum of their 3D gates may each take the other's nearest blobs (dense
  // clusters, markers passing each other), and a wrong pick makes a swapped or ghost point. Their
  // blobs go to the matcher, whose epipolar consistency decides, and the tracker's assignment
  // gives the points to the tracks. 0 serves every prediction (faster, less safe).
  double contested_gate_factor = 1.5;
  // Gates count up to this (mm) in that test: a fast track's wide gate says its own velocity is
  // uncertain, not that its neighbours are near (the serve's racket hand: markers ~100 mm apart
  // whose predictions the triangulation checks still tell apart).
  double contested_gate_cap_mm = 30.0;
  // Contested predictions resolved jointly (recon/contested_groups.h: an optimal assignment of
  // each group's predictions to blobs per camera) before the matcher; the matcher then gets
  // only the blobs no point took. Off by default: on the dense set 3.3x faster with a better
  // rmse, but 3 more trajectories and 4 more swaps, and the shared motions' outputs move
  // (recon/README.md, issue 39). false: every contested prediction's blobs go to the matcher.
  bool resolve_contested_groups = false;
  // Two predictions whose reprojections fall within this of one blob (pixels) share it: two
  // markers a pixel or two apart in that image make one round blob that the node's shape test
  // cannot flag, whose centroid is off for both. It is then treated as a merged blob (left out
  // of the solve while two other views remain). 0 turns this off.
  double coincident_px = 2.0;

  void Check() const;
};

struct GhostFilterOptions {
  bool enabled = true;
  // Two markers' centres are at least a marker diameter apart: points closer than this are one.
  double min_separation_mm = 10.0;

  void Check() const;
};

enum class MatcherType { kRelaxation, kClustering, kGreedy };

// "relaxation" | "clustering" | "greedy"; FromString throws std::invalid_argument on others.
std::string MatcherTypeToString(MatcherType type);
MatcherType MatcherTypeFromString(const std::string& name);

struct ReconstructorOptions {
  MatcherType matcher = MatcherType::kRelaxation;
  bool use_predictions = true;
  // A marker no track predicted needs this many views. Two rays always meet somewhere, so a
  // two-view point may be a ghost within one frame: the matchers accept them after every point
  // of three or more views and only where few other cameras should see them
  // (triangulation.two_view_max_unseen), and the tracker confirms a track begun on them only
  // once it persisted and moved like a marker (tracker.two_view_birth_frames). 3: never.
  int min_views_without_prediction = 2;
  // Centroid noise sigma per image axis (px) the gates follow (recon/rig_noise.h). 0: the
  // calibration's (cameras' centroid_rms_px), then measured from the residuals continuously.
  double centroid_noise_px = 0.0;
  // Whether the gates follow the noise measured from the residuals (centroid_noise_px 0). A
  // calibration monitor holds them to the calibration's noise instead: a bumped camera's
  // residuals are the miscalibration it looks for, not noise to open the gates to.
  bool follow_measured_noise = true;
  TriangulationOptions triangulation;
  EpipolarGraphOptions graph;
  RelaxationOptions relaxation;
  ClusteringOptions clustering;
  PredictionMatchOptions prediction;
  GhostFilterOptions ghosts;
  // Acquisition on large rigs: when more blobs than this per camera are left to the matcher (the
  // first frame, everything lost at once), it first works on at most seed_cameras cameras spread
  // around the volume, their points take their views in every other camera, and only what is
  // left goes to a matcher over all cameras. The all-pairs graph grows with cameras squared
  // times blobs squared; this bounds a cold start at 16-64 cameras to about an 8-camera one
  // (bench: 16 x 150 first frame 67 -> 14 ms, 64 x 100 896 -> ~30 ms).
  // 0 seed cameras: always match over all cameras.
  int seed_cameras = 8;
  double seed_from_blobs_per_camera = 4.0;
  // Worker threads for one frame (undistortion and the blob index per camera, prediction
  // serving); results are identical for every count. 1: the calling thread only.
  int threads = 1;

  void Check() const;
};

}  // namespace mocap

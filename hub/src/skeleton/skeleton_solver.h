// Per-frame skeleton solve: the root's pose and every joint angle fitted to one frame's labelled
// markers by Ceres (Levenberg-Marquardt with the joints' limits as bounds, a Cauchy loss on each
// marker's distance so that one mislabelled or stray marker cannot drag the pose), warm-started
// from the previous frame and started afresh (the root's markers by Kabsch, joints at rest, a
// first solve under a convex Huber loss) on the first frame, after a frame that could not be
// solved, or when the warm start ends far off (its median marker residual).
// Missing markers (NaN) simply add nothing. Markers are in skeleton space (skeleton.h).
// Errors: options and mis-sized inputs throw std::invalid_argument.
#pragma once

#include <memory>
#include <vector>

#include <Eigen/Core>

#include "skeleton/skeleton.h"

namespace mocap {

struct SkeletonSolveOptions {
  double loss_scale_mm = 10.0;  // Cauchy: markers much further off than this count little
  int max_iterations = 30;  // a fresh start's solves
  int warm_iterations = 30;  // a warm-started solve (live: fewer, its cost bounded on the loop)
  // A warm start whose median marker residual ends above this is tried again from a fresh start
  // (the median: a few misnamed markers, far off under the robust loss, do not call for one).
  double restart_median_mm = 30.0;
  // Fewer visible markers than this: the frame is not solved.
  int min_markers = 4;
  void Check() const;
};

struct SkeletonFrameFit {
  bool solved = false;
  std::vector<double> pose;         // Skeleton::NumPoseParameters(); angles in radians
  std::vector<double> residual_mm;  // per skeleton marker: distance to its observation, NaN when absent
  double rms_mm = 0.0, max_mm = 0.0, median_mm = 0.0;
  int markers = 0;  // visible markers used
  int iterations = 0;
  bool restarted = false;
};

class SkeletonSolver {
 public:
  SkeletonSolver(const Skeleton& skeleton, const SkeletonSolveOptions& options);
  ~SkeletonSolver();
  SkeletonSolver(const SkeletonSolver&) = delete;
  SkeletonSolver& operator=(const SkeletonSolver&) = delete;

  // observed: one point per skeleton marker, in skeleton space, NaN for a gap.
  SkeletonFrameFit Solve(const std::vector<Eigen::Vector3d>& observed);
  // Forgets the warm start (a cut in the recording).
  void Reset() { has_previous_ = false; }

 private:
  struct Impl;
  bool FreshStart();
  void RunSolver(SkeletonFrameFit* fit);

  std::unique_ptr<Impl> impl_;
  bool has_previous_ = false;
};

// A fresh start's root pose: rotation and translation that carry the rest pose's markers (root at
// the origin, joints at zero) onto the observed ones, by Kabsch over the root segment's markers
// when 3 or more are seen, otherwise over every seen marker. Fills the root part of `pose` and
// zeroes the joints; false when fewer than 3 markers are seen.
bool InitialRootPose(const Skeleton& skeleton, const std::vector<Eigen::Vector3d>& observed, std::vector<double>* pose);

// Angles about `axes` (applied in that order, each successive pair distinct) that make rotation r.
Eigen::Vector3d EulerFromRotation(const Eigen::Matrix3d& r, int a0, int a1, int a2);

}  // namespace mocap

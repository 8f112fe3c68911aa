// A whole recording solved frame by frame (skeleton_solver.h) in order: the motion for the
// writers (motion_files.h) and the marker residuals over the trial.
#pragma once

#include <vector>

#include "io/marker_trajectories.h"
#include "skeleton/motion_files.h"
#include "skeleton/skeleton_solver.h"

namespace mocap {

struct TrialSolve {
  SkeletonMotion motion;
  std::vector<SkeletonFrameFit> frames;
  size_t solved_frames = 0;
  double rms_mm = 0.0, max_mm = 0.0;  // over every visible marker of every solved frame
  double seconds = 0.0;               // solver time (wall clock), for benchmarks
};

// markers: in skeleton space, named like the skeleton's markers (others ignored).
TrialSolve SolveTrial(const Skeleton& skeleton, const MarkerTrajectories& markers, const SkeletonSolveOptions& options);

}  // namespace mocap

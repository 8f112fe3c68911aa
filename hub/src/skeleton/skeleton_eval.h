// `skeleton eval`: a solved motion against the simulator's truth: joint-angle RMS per joint (over
// its degrees of freedom and the frames both have) and per degree of freedom, and each segment's
// length error (distance from its parent's joint centre: the bone's or offset's length).
// Segments and dofs are matched by name and axis; the root's rotations are not joint angles.
#pragma once

#include <string>
#include <vector>

#include "skeleton/motion_files.h"
#include "skeleton/skeleton.h"

namespace mocap {

struct JointAngleError {
  std::string segment;
  double rms_deg = 0.0;          // over all its dofs and frames
  std::vector<double> dof_rms_deg;  // per dof, in the segment's order
  size_t frames = 0;
};

struct SegmentLengthError {
  std::string segment;
  double truth_mm = 0.0, estimate_mm = 0.0, error_mm = 0.0;  // error = estimate - truth
};

struct SkeletonEvalReport {
  std::vector<JointAngleError> joints;
  std::vector<SegmentLengthError> lengths;
};

// Frames are paired by index; only frames solved in `estimate` count. Throws std::invalid_argument
// when the skeletons' segments or dofs differ.
SkeletonEvalReport EvaluateSkeleton(const Skeleton& truth, const SkeletonMotion& truth_motion, const Skeleton& estimate,
                                    const SkeletonMotion& estimate_motion);

}  // namespace mocap

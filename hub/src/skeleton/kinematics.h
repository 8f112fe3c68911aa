// Forward kinematics of a skeleton (skeleton.h) for a pose vector: every segment's rotation and
// joint centre in skeleton space, each rotation's axis in skeleton space (for analytic Jacobians:
// a point p carried by a rotation about axis a through centre c moves as a x (p - c) per radian),
// and markers' positions. The pose vector: the root's translation (mm), then each segment's
// angles in radians, in segment order (Skeleton::FirstDof). Pure, allocation-free once sized.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "skeleton/skeleton.h"

namespace mocap {

// Rotation about axis 0/1/2 (x/y/z) by `angle` radians.
Eigen::Matrix3d AxisRotation(int axis, double angle);

struct SkeletonPoseState {
  std::vector<Eigen::Matrix3d> rotation;  // per segment: skeleton space from the segment's frame
  std::vector<Eigen::Vector3d> origin;    // per segment: joint centre in skeleton space
  std::vector<Eigen::Vector3d> axis;      // per pose parameter: rotation axis (translations unused)
  std::vector<int> dof_segment;           // per pose parameter: the segment it turns (-1: translation)
};

// Segments from the root down to each segment (inclusive), precomputed once per skeleton.
std::vector<std::vector<int>> SegmentChains(const Skeleton& skeleton);

// offsets: per segment, replaces the skeleton's joint offsets (calibration); nullptr uses them.
void ForwardKinematics(const Skeleton& skeleton, const double* pose, const Eigen::Vector3d* offsets,
                       SkeletonPoseState* state);

inline Eigen::Vector3d MarkerInSkeleton(const SkeletonPoseState& state, int segment, const Eigen::Vector3d& offset) {
  return state.origin[segment] + state.rotation[segment] * offset;
}

// Pose vector limits in radians (translations and the root's rotations unbounded: +-inf).
void PoseBounds(const Skeleton& skeleton, std::vector<double>* lower, std::vector<double>* upper);

}  // namespace mocap

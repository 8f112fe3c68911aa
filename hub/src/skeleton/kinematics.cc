// Forward kinematics: one pass from the root down (parents come before children).
#include "skeleton/kinematics.h"

#include <cmath>
#include <limits>

namespace mocap {

Eigen::Matrix3d AxisRotation(int axis, double angle) {
  const double c = std::cos(angle), s = std::sin(angle);
  Eigen::Matrix3d r;
  switch (axis) {
    case 0: r << 1, 0, 0, 0, c, -s, 0, s, c; break;
    case 1: r << c, 0, s, 0, 1, 0, -s, 0, c; break;
    default: r << c, -s, 0, s, c, 0, 0, 0, 1; break;
  }
  return r;
}

std::vector<std::vector<int>> SegmentChains(const Skeleton& skeleton) {
  std::vector<std::vector<int>> chains(skeleton.NumSegments());
  for (size_t s = 0; s < skeleton.NumSegments(); ++s) {
    if (skeleton.segments[s].parent >= 0) chains[s] = chains[skeleton.segments[s].parent];
    chains[s].push_back(static_cast<int>(s));
  }
  return chains;
}

void ForwardKinematics(const Skeleton& skeleton, const double* pose, const Eigen::Vector3d* offsets,
                       SkeletonPoseState* state) {
  const size_t n = skeleton.NumSegments();
  const size_t params = skeleton.NumPoseParameters();
  state->rotation.resize(n);
  state->origin.resize(n);
  state->axis.resize(params);
  state->dof_segment.resize(params);
  for (int i = 0; i < 3; ++i) state->dof_segment[i] = -1;
  size_t k = 3;
  for (size_t s = 0; s < n; ++s) {
    const SkeletonSegment& segment = skeleton.segments[s];
    Eigen::Matrix3d r;
    if (segment.parent < 0) {
      r.setIdentity();
      state->origin[s] = Eigen::Vector3d(pose[0], pose[1], pose[2]);
    } else {
      r = state->rotation[segment.parent];
      state->origin[s] = state->origin[segment.parent] + r * (offsets ? offsets[s] : segment.offset);
    }
    for (const JointDof& dof : segment.dofs) {
      state->axis[k] = r.col(dof.axis);
      state->dof_segment[k] = static_cast<int>(s);
      r = r * AxisRotation(dof.axis, pose[k]);
      ++k;
    }
    state->rotation[s] = r;
  }
}

void PoseBounds(const Skeleton& skeleton, std::vector<double>* lower, std::vector<double>* upper) {
  const double inf = std::numeric_limits<double>::infinity();
  lower->assign(skeleton.NumPoseParameters(), -inf);
  upper->assign(skeleton.NumPoseParameters(), inf);
  // The root turns freely (a heading wraps around); its listed limits are not used.
  size_t k = 3 + skeleton.segments[0].dofs.size();
  for (size_t s = 1; s < skeleton.NumSegments(); ++s)
    for (const JointDof& dof : skeleton.segments[s].dofs) {
      (*lower)[k] = dof.min_deg * M_PI / 180.0;
      (*upper)[k] = dof.max_deg * M_PI / 180.0;
      ++k;
    }
}

}  // namespace mocap

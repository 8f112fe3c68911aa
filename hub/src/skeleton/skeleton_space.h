// Skeleton space (+y up) and a recording's world (+x, +y or +z up): a fixed rotation between them,
// so that an upright subject's root turns mainly about y and its Euler angles stay far from gimbal
// lock. BVH and ASF/AMC files are written in skeleton space (their usual +y up).
#pragma once

#include <Eigen/Core>

#include "io/marker_trajectories.h"

namespace mocap {

// Rotation taking skeleton-space vectors to world vectors; up_axis 0, 1, 2 (x, y, z).
Eigen::Matrix3d WorldFromSkeletonSpace(int up_axis);

// Every point turned into skeleton space (gaps stay gaps).
MarkerTrajectories ToSkeletonSpace(const MarkerTrajectories& world, int up_axis);
MarkerTrajectories ToWorld(const MarkerTrajectories& skeleton_space, int up_axis);

}  // namespace mocap

// Quarter turns between +y up and the recording's up axis.
#include "skeleton/skeleton_space.h"

#include <stdexcept>

namespace mocap {
namespace {

MarkerTrajectories Turned(const MarkerTrajectories& in, const Eigen::Matrix3d& r) {
  MarkerTrajectories out = in;
  for (Eigen::Vector3d& p : out.points)
    if (!MarkerTrajectories::IsGap(p)) p = r * p;
  return out;
}

}  // namespace

Eigen::Matrix3d WorldFromSkeletonSpace(int up_axis) {
  Eigen::Matrix3d r;
  switch (up_axis) {
    case 0: r << 0, 1, 0, -1, 0, 0, 0, 0, 1; break;  // y -> x, x -> -y
    case 1: r.setIdentity(); break;
    case 2: r << 1, 0, 0, 0, 0, -1, 0, 1, 0; break;  // y -> z, z -> -y
    default: throw std::invalid_argument("up axis: " + std::to_string(up_axis) + " is not 0, 1 or 2");
  }
  return r;
}

MarkerTrajectories ToSkeletonSpace(const MarkerTrajectories& world, int up_axis) {
  return Turned(world, WorldFromSkeletonSpace(up_axis).transpose());
}

MarkerTrajectories ToWorld(const MarkerTrajectories& skeleton_space, int up_axis) {
  return Turned(skeleton_space, WorldFromSkeletonSpace(up_axis));
}

}  // namespace mocap

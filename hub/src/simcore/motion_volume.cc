// Motion bounding box.
#include "simcore/motion_volume.h"

#include <cstdio>
#include <stdexcept>

namespace mocap {

MotionVolume ComputeMotionVolume(const MarkerTrajectories& motion, int up_axis) {
  MotionVolume volume;
  volume.min = Eigen::Vector3d::Constant(1e300);
  volume.max = Eigen::Vector3d::Constant(-1e300);
  bool any = false;
  for (const Eigen::Vector3d& point : motion.points) {
    if (MarkerTrajectories::IsGap(point)) continue;
    volume.min = volume.min.cwiseMin(point);
    volume.max = volume.max.cwiseMax(point);
    any = true;
  }
  if (!any) throw std::runtime_error("the motion has no marker positions");
  const double side = (volume.max - volume.min).maxCoeff();
  if (!(side <= kMaxVolumeSideMm) || !volume.Center().allFinite()) {
    char text[160];
    std::snprintf(text, sizeof text, "the motion spans %.3g mm: more than a capture volume can (1 km); check its "
                  "units and values", side);
    throw std::runtime_error(text);
  }
  if (up_axis < 0) {
    up_axis = DetectUpAxis(motion);
    if (up_axis < 0) {
      throw std::runtime_error("cannot detect the up axis (no frame with three markers); give --up");
    }
  }
  if (up_axis > 2) throw std::runtime_error("up axis must be x, y or z");
  volume.up_axis = up_axis;
  return volume;
}

}  // namespace mocap

// Motion bounding box and up-axis detection.
#include "sim/motion_volume.h"

#include <algorithm>
#include <stdexcept>
#include <vector>

namespace mocap {

int DetectUpAxis(const MarkerTrajectories& motion) {
  std::vector<double> spreads[3];
  for (size_t f = 0; f < motion.NumFrames(); ++f) {
    Eigen::Vector3d low = Eigen::Vector3d::Constant(1e300), high = Eigen::Vector3d::Constant(-1e300);
    int present = 0;
    for (size_t m = 0; m < motion.NumMarkers(); ++m) {
      if (!motion.Has(f, m)) continue;
      low = low.cwiseMin(motion.At(f, m));
      high = high.cwiseMax(motion.At(f, m));
      ++present;
    }
    if (present < 3) continue;
    for (int axis = 0; axis < 3; ++axis) spreads[axis].push_back(high[axis] - low[axis]);
  }
  if (spreads[0].empty()) return -1;
  int best = 0;
  double best_median = -1.0;
  for (int axis = 0; axis < 3; ++axis) {
    std::vector<double>& values = spreads[axis];
    std::nth_element(values.begin(), values.begin() + values.size() / 2, values.end());
    const double median = values[values.size() / 2];
    if (median > best_median) {
      best_median = median;
      best = axis;
    }
  }
  return best;
}

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

// Reprojection sums that leave unprojectable observations out and say how many there were.
#include "calib/reprojection_sum.h"

#include <cmath>

namespace mocap {

bool ReprojectionSum::Add(const Camera& camera, const Eigen::Vector3d& point_in_world,
                          const Eigen::Vector2d& observed) {
  Eigen::Vector2d projected;
  if (!camera.ProjectToPixel(point_in_world, &projected)) {
    ++unprojected;
    return false;
  }
  squared_px += (projected - observed).squaredNorm();
  ++observations;
  return true;
}

double ReprojectionSum::RmsPx() const {
  return observations > 0 ? std::sqrt(squared_px / static_cast<double>(observations)) : 0.0;
}

}  // namespace mocap

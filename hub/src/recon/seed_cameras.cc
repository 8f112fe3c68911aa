// Farthest-point sampling of camera centres.
#include "recon/seed_cameras.h"

#include <algorithm>
#include <limits>

namespace mocap {

std::vector<char> SpreadCameras(const RigModel& rig, int count) {
  const int n = rig.NumCameras();
  if (count <= 0 || n <= count) return {};
  std::vector<char> chosen(n, 0);
  // Squared distance from each camera to the nearest chosen one.
  std::vector<double> nearest(n, std::numeric_limits<double>::infinity());
  int next = 0;
  for (int k = 0; k < count; ++k) {
    chosen[next] = 1;
    const Eigen::Vector3d& centre = rig.camera(next).center_in_world;
    int farthest = -1;
    for (int c = 0; c < n; ++c) {
      nearest[c] = std::min(nearest[c], (rig.camera(c).center_in_world - centre).squaredNorm());
      if (!chosen[c] && (farthest < 0 || nearest[c] > nearest[farthest])) farthest = c;
    }
    next = farthest;
  }
  return chosen;
}

}  // namespace mocap

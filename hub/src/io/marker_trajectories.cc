// Helpers of the shared trajectory type.
#include "io/marker_trajectories.h"

#include <algorithm>
#include <cstdio>
#include <vector>

namespace mocap {

std::string DefaultMarkerName(size_t index) {
  char name[32];
  std::snprintf(name, sizeof(name), "M%03zu", index + 1);
  return name;
}

bool IsAnonymousMarkerName(const std::string& name) {
  return name.size() >= 2 && name[0] == 'M' &&
         std::all_of(name.begin() + 1, name.end(), [](char c) { return c >= '0' && c <= '9'; });
}

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

}  // namespace mocap

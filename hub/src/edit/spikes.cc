// Spike detection by a robust acceleration limit (see spikes.h).
#include "edit/spikes.h"

#include <algorithm>
#include <cmath>

namespace mocap::edit {
namespace {

constexpr size_t kMinAccelerations = 8;
constexpr double kFloorMmPerFrame2 = 0.01;

double Median(std::vector<double> values) {
  const size_t mid = values.size() / 2;
  std::nth_element(values.begin(), values.begin() + static_cast<long>(mid), values.end());
  return values[mid];
}

}  // namespace

std::vector<Spike> FindSpikes(const EditedTake& take, size_t marker, size_t first, size_t last, double threshold) {
  const MarkerTrajectories& m = take.markers;
  const size_t frames = m.NumFrames();
  std::vector<double> accel(frames, -1.0);  // -1: not measurable here
  std::vector<double> values;
  for (size_t f = std::max<size_t>(first, 1); f + 1 < frames && f <= last; ++f) {
    if (!m.Has(f - 1, marker) || !m.Has(f, marker) || !m.Has(f + 1, marker)) continue;
    accel[f] = (m.At(f + 1, marker) - 2.0 * m.At(f, marker) + m.At(f - 1, marker)).norm();
    values.push_back(accel[f]);
  }
  std::vector<Spike> spikes;
  if (values.size() < kMinAccelerations) return spikes;
  const double median = Median(values);
  for (double& v : values) v = std::abs(v - median);
  const double scale = std::max(1.4826 * Median(values), kFloorMmPerFrame2);
  const double limit = median + threshold * scale;
  for (size_t f = 0; f < frames; ++f) {
    if (accel[f] <= limit) continue;
    const bool peak = (f == 0 || accel[f] >= accel[f - 1]) && (f + 1 >= frames || accel[f] > accel[f + 1]);
    if (peak) spikes.push_back({marker, f, accel[f], limit});
  }
  return spikes;
}

}  // namespace mocap::edit

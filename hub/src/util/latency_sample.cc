// Reservoir of latencies (see latency_sample.h).
#include "util/latency_sample.h"

#include <algorithm>

namespace mocap {

void LatencySample::Add(double value) {
  ++count_;
  if (count_ == 1 || value > max_) max_ = value;
  if (values_.size() < capacity_) {
    values_.push_back(value);
    return;
  }
  const uint64_t slot = std::uniform_int_distribution<uint64_t>(0, count_ - 1)(rng_);
  if (slot < capacity_) values_[slot] = value;
}

double LatencySample::Percentile(double p) const {
  if (values_.empty()) return 0.0;
  std::vector<double> v = values_;
  const double clamped = std::clamp(p, 0.0, 100.0);
  const size_t k = std::min(v.size() - 1, static_cast<size_t>(clamped / 100.0 * static_cast<double>(v.size())));
  std::nth_element(v.begin(), v.begin() + static_cast<long>(k), v.end());
  return v[k];
}

}  // namespace mocap

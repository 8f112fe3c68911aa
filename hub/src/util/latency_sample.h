// Latencies of a long-running process in constant memory: a uniform reservoir of at most
// `capacity` values (Vitter's algorithm R, seeded, so a run replays), plus the exact count and
// maximum. Percentiles are of the reservoir, exact until it fills.
#pragma once

#include <cstdint>
#include <random>
#include <vector>

namespace mocap {

class LatencySample {
 public:
  explicit LatencySample(size_t capacity = 100000) : capacity_(capacity) {}
  void Add(double value);
  // p in [0, 100]; 0 when empty.
  double Percentile(double p) const;
  double max() const { return max_; }
  uint64_t count() const { return count_; }

 private:
  size_t capacity_;
  std::vector<double> values_;
  uint64_t count_ = 0;
  double max_ = 0.0;
  std::mt19937_64 rng_{7};
};

}  // namespace mocap

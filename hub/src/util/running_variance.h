// Welford's running mean and variance, one sample at a time: the rigid model's links and the
// hindsight repair's steady distances both keep their distances so (count, mean and the sum of
// squared deviations, beside their own flags).
#pragma once

namespace mocap {

// Adds x to the statistics of *count samples (mean, m2: sum of squared deviations).
inline void AddToRunningVariance(double x, int* count, double* mean, double* m2) {
  ++*count;
  const double delta = x - *mean;
  *mean += delta / *count;
  *m2 += delta * (x - *mean);
}

}  // namespace mocap

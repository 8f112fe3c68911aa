#include "detect-bench/bench_timing.h"

#include <algorithm>
#include <ctime>

namespace mocap {

double ThreadCpuMs() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return ts.tv_sec * 1e3 + ts.tv_nsec / 1e6;
}

double TimePerFrame(const std::vector<BenchFrame>& frames, int repeat,
                    const std::function<void(const BenchFrame&)>& work) {
  for (const BenchFrame& f : frames) work(f);
  double best = 1e300;
  for (int r = 0; r < repeat; ++r) {
    const double t0 = ThreadCpuMs();
    for (const BenchFrame& f : frames) work(f);
    best = std::min(best, ThreadCpuMs() - t0);
  }
  return best / static_cast<double>(frames.size());
}

}  // namespace mocap

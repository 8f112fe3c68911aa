// CPU time of benchmark passes over in-memory frames (mocap-detect-bench).
#pragma once

#include <functional>
#include <vector>

#include "detect-bench/frame_set.h"

namespace mocap {

// This thread's CPU time in ms: on a shared machine, time spent preempted is not counted.
double ThreadCpuMs();

// Best (smallest) CPU time per frame in ms over `repeat` passes over all frames, after a
// warm-up pass; the minimum is the figure least disturbed by other work on the machine.
double TimePerFrame(const std::vector<BenchFrame>& frames, int repeat,
                    const std::function<void(const BenchFrame&)>& work);

}  // namespace mocap

// Prints what the per-frame solve costs on one thread: a simulated 20-segment subject (the HDM05
// set with toe markers) walking for 20 s at 60 Hz, soft-tissue wobble 2 mm, solved frame by frame
// with warm starts (the steady state of offline and live solving).
//   skeleton_solve_benchmark [seconds]
#include <chrono>
#include <cmath>
#include <ctime>
#include <cstdio>
#include <cstdlib>

#include "skeleton/skeleton_sim.h"
#include "skeleton/skeleton_solver.h"
#include "skeleton/skeleton_testing.h"

int main(int argc, char** argv) {
  mocap::SkeletonSimOptions options;
  options.motion = mocap::SkeletonSimMotion::kGait;
  options.duration_s = argc > 1 ? std::atof(argv[1]) : 20.0;
  const mocap::SkeletonSimulation sim = mocap::SimulateSkeleton(mocap::TwentySegmentTemplate(), options);
  mocap::SkeletonSolver solver(sim.subject, mocap::SkeletonSolveOptions{});
  const size_t frames = sim.markers.NumFrames(), markers = sim.markers.NumMarkers();
  std::vector<std::vector<Eigen::Vector3d>> observed(frames);
  for (size_t f = 0; f < frames; ++f)
    for (size_t m = 0; m < markers; ++m) observed[f].push_back(sim.markers.At(f, m));
  double worst = 0.0, rms = 0.0;
  int iterations = 0;
  const auto start = std::chrono::steady_clock::now();
  const std::clock_t cpu_start = std::clock();
  for (size_t f = 0; f < frames; ++f) {
    const auto t0 = std::chrono::steady_clock::now();
    const mocap::SkeletonFrameFit fit = solver.Solve(observed[f]);
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    if (f > 0) worst = std::max(worst, ms);
    rms += fit.rms_mm * fit.rms_mm;
    iterations += fit.iterations;
  }
  const double total = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  // CPU time as well: on a shared machine the wall clock also counts other processes' turns.
  const double cpu = 1000.0 * static_cast<double>(std::clock() - cpu_start) / CLOCKS_PER_SEC;
  std::printf("skeleton solve: %zu segments, %zu dofs, %zu markers, %zu frames: %.3f ms CPU per frame (one thread), "
              "%.3f ms wall, slowest %.3f ms wall, %.1f iterations per frame, marker rms %.2f mm\n",
              sim.subject.NumSegments(), sim.subject.NumPoseParameters(), markers, frames, cpu / frames, total / frames,
              worst,
              static_cast<double>(iterations) / frames, std::sqrt(rms / frames));
  return 0;
}

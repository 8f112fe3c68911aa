// Frame-by-frame solve of a recording; a gap in frame numbers restarts the warm start.
#include "skeleton/trial_solve.h"

#include <chrono>
#include <cmath>

#include "skeleton/subject_calibration.h"

namespace mocap {

TrialSolve SolveTrial(const Skeleton& skeleton, const MarkerTrajectories& markers, const SkeletonSolveOptions& options) {
  TrialSolve result;
  result.motion.rate_hz = markers.rate_hz;
  SkeletonSolver solver(skeleton, options);
  const std::vector<int> columns = MarkerColumns(skeleton, markers);
  double sum = 0.0;
  size_t count = 0;
  const auto start = std::chrono::steady_clock::now();
  for (size_t f = 0; f < markers.NumFrames(); ++f) {
    if (f > 0 && markers.frame_numbers[f] != markers.frame_numbers[f - 1] + 1) solver.Reset();
    SkeletonFrameFit fit = solver.Solve(FrameObservations(markers, columns, f));
    if (fit.solved) {
      ++result.solved_frames;
      for (double r : fit.residual_mm)
        if (std::isfinite(r)) {
          sum += r * r;
          ++count;
          result.max_mm = std::max(result.max_mm, r);
        }
      result.motion.poses.push_back(fit.pose);
    } else {
      result.motion.poses.emplace_back();
    }
    result.frames.push_back(std::move(fit));
  }
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  result.rms_mm = count ? std::sqrt(sum / count) : 0.0;
  return result;
}

}  // namespace mocap

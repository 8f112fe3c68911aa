// The Ceres settings the small exact solves of calibration share (a camera found again, the
// cameras refined with the others held, single-marker wanding): tolerances so tight that a solve
// ends at its minimum or its iteration limit, never early on a flat stretch, and no logging
// (libraries do not print). Written once so that the solves cannot drift apart.
#pragma once

#include <ceres/solver.h>

namespace mocap {

ceres::Solver::Options TightSolverOptions(ceres::LinearSolverType linear_solver, int max_iterations,
                                          int num_threads = 1);

}  // namespace mocap

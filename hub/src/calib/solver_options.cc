// Shared Ceres settings (see solver_options.h).
#include "calib/solver_options.h"

namespace mocap {

ceres::Solver::Options TightSolverOptions(ceres::LinearSolverType linear_solver, int max_iterations,
                                          int num_threads) {
  ceres::Solver::Options solver;
  solver.linear_solver_type = linear_solver;
  solver.max_num_iterations = max_iterations;
  solver.num_threads = num_threads;
  solver.function_tolerance = 1e-12;
  solver.gradient_tolerance = 1e-14;
  solver.parameter_tolerance = 1e-12;
  solver.logging_type = ceres::SILENT;
  return solver;
}

}  // namespace mocap

// Assignment of predictions (rows) to measurements (columns) under a gate: the seed's sorted
// greedy (seed 001 section 4.2: all gated pairs by increasing distance, each side used once) and
// the optimal one (most pairs, then least total cost; util/assignment.h).
#pragma once

#include <vector>

#include <Eigen/Core>

#include "track/track_options.h"

namespace mocap {

// For each row the assigned column or -1. Costs above `gate` (per row: gates[row]) are
// forbidden. `gates` may be empty to use `gate` everywhere.
std::vector<int> AssignGreedySorted(const Eigen::MatrixXd& cost, const std::vector<double>& gates);
std::vector<int> AssignOptimal(const Eigen::MatrixXd& cost, const std::vector<double>& gates);
std::vector<int> Assign(AssignmentMethod method, const Eigen::MatrixXd& cost,
                        const std::vector<double>& gates);

}  // namespace mocap

// Assignment of predictions (rows) to measurements (columns) under a gate: the seed's sorted
// greedy (seed 001 section 4.2: all gated pairs by increasing distance, each side used once) and
// the optimal one (most pairs, then least total cost; util/assignment.h).
#pragma once

#include <vector>

#include <Eigen/Core>

#include "track/track_options.h"

namespace mocap {

// For each row the assigned column or -1. `gates` holds one gate per row; costs above
// gates[row] (or not finite) are forbidden. A cost matrix without rows or columns gives every row
// -1. Throws std::invalid_argument when gates.size() differs from cost.rows().
std::vector<int> AssignGreedySorted(const Eigen::MatrixXd& cost, const std::vector<double>& gates);
std::vector<int> AssignOptimal(const Eigen::MatrixXd& cost, const std::vector<double>& gates);
std::vector<int> Assign(AssignmentMethod method, const Eigen::MatrixXd& cost,
                        const std::vector<double>& gates);

}  // namespace mocap

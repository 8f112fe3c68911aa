// Gated greedy and optimal assignment.
#include "track/assignment.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <tuple>

#include "util/assignment.h"

namespace mocap {
namespace {

// Both assigners index gates by row: a short vector would be read out of bounds.
void CheckGates(const Eigen::MatrixXd& cost, const std::vector<double>& gates) {
  if (static_cast<Eigen::Index>(gates.size()) != cost.rows()) {
    throw std::invalid_argument("assignment: " + std::to_string(gates.size()) + " gates for " +
                                std::to_string(cost.rows()) + " rows");
  }
}

}  // namespace

std::vector<int> AssignGreedySorted(const Eigen::MatrixXd& cost, const std::vector<double>& gates) {
  CheckGates(cost, gates);
  std::vector<std::tuple<double, int, int>> pairs;
  for (int r = 0; r < cost.rows(); ++r) {
    for (int c = 0; c < cost.cols(); ++c) {
      if (std::isfinite(cost(r, c)) && cost(r, c) <= gates[r]) pairs.emplace_back(cost(r, c), r, c);
    }
  }
  std::sort(pairs.begin(), pairs.end());
  std::vector<int> column_of_row(cost.rows(), -1);
  std::vector<bool> column_used(cost.cols(), false);
  for (const auto& [value, r, c] : pairs) {
    if (column_of_row[r] >= 0 || column_used[c]) continue;
    column_of_row[r] = c;
    column_used[c] = true;
  }
  return column_of_row;
}

std::vector<int> AssignOptimal(const Eigen::MatrixXd& cost, const std::vector<double>& gates) {
  CheckGates(cost, gates);
  if (cost.rows() == 0 || cost.cols() == 0) return std::vector<int>(cost.rows(), -1);
  // Per-row gates become infinite costs, then the shared solver runs with an open gate.
  Eigen::MatrixXd gated = cost;
  double widest = 0.0;
  for (double gate : gates) widest = std::max(widest, gate);
  for (int r = 0; r < cost.rows(); ++r) {
    for (int c = 0; c < cost.cols(); ++c) {
      if (!(cost(r, c) <= gates[r])) gated(r, c) = std::numeric_limits<double>::infinity();
    }
  }
  return SolveAssignment(gated, widest);
}

std::vector<int> Assign(AssignmentMethod method, const Eigen::MatrixXd& cost,
                        const std::vector<double>& gates) {
  return method == AssignmentMethod::kGreedy ? AssignGreedySorted(cost, gates)
                                             : AssignOptimal(cost, gates);
}

}  // namespace mocap

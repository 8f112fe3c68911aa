// Optimal one-to-one assignment (minimum total cost) for rectangular cost matrices: the
// Hungarian method with potentials (Jonker-Volgenant style shortest augmenting paths),
// O(n^2 m). Used by eval (matching reconstructed points to truth) and open to recon/track.
#pragma once

#include <vector>

#include <Eigen/Core>

namespace mocap {

// Pairs that cost more than `gate` (or are not finite) are forbidden. Returns, for each row, the
// assigned column or -1. Among all assignments it maximises the number of pairs first and then
// minimises their total cost. Rows and columns may differ in number.
std::vector<int> SolveAssignment(const Eigen::MatrixXd& cost, double gate);

}  // namespace mocap

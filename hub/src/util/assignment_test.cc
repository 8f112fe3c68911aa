// Tests of the optimal assignment against brute force on random gated problems.
#include "util/assignment.h"

#include <algorithm>
#include <numeric>
#include <random>

#include <gtest/gtest.h>

namespace mocap {
namespace {

// Best (most pairs, then least cost) by enumerating every injective map of the smaller side.
std::pair<int, double> BruteForce(const Eigen::MatrixXd& cost, double gate) {
  std::pair<int, double> best{-1, 0.0};
  const bool transpose = cost.rows() > cost.cols();
  const Eigen::MatrixXd m = transpose ? Eigen::MatrixXd(cost.transpose()) : cost;
  std::vector<int> cols(m.cols());
  std::iota(cols.begin(), cols.end(), 0);
  do {
    int pairs = 0;
    double total = 0.0;
    for (Eigen::Index r = 0; r < m.rows(); ++r) {
      if (m(r, cols[r]) <= gate) {
        ++pairs;
        total += m(r, cols[r]);
      }
    }
    if (pairs > best.first || (pairs == best.first && total < best.second)) best = {pairs, total};
  } while (std::next_permutation(cols.begin(), cols.end()));
  return best;
}

TEST(AssignmentTest, MatchesBruteForce) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> uniform(0.0, 30.0);
  for (int trial = 0; trial < 300; ++trial) {
    const int rows = 1 + trial % 6;
    const int cols = 1 + (trial / 6) % 6;
    Eigen::MatrixXd cost(rows, cols);
    for (int r = 0; r < rows; ++r) {
      for (int c = 0; c < cols; ++c) cost(r, c) = uniform(rng);
    }
    const double gate = 20.0;
    const std::vector<int> assigned = SolveAssignment(cost, gate);
    ASSERT_EQ(assigned.size(), static_cast<size_t>(rows));
    int pairs = 0;
    double total = 0.0;
    std::vector<int> seen;
    for (int r = 0; r < rows; ++r) {
      if (assigned[r] < 0) continue;
      ASSERT_LT(assigned[r], cols);
      EXPECT_LE(cost(r, assigned[r]), gate);
      seen.push_back(assigned[r]);
      ++pairs;
      total += cost(r, assigned[r]);
    }
    std::sort(seen.begin(), seen.end());
    EXPECT_EQ(std::adjacent_find(seen.begin(), seen.end()), seen.end()) << "column used twice";
    const auto best = BruteForce(cost, gate);
    EXPECT_EQ(pairs, best.first) << "trial " << trial;
    EXPECT_NEAR(total, best.second, 1e-9) << "trial " << trial;
  }
}

TEST(AssignmentTest, PrefersGlobalOptimumOverGreedy) {
  // Greedy would take (0,0)=1 and leave row 1 with 10; the optimum is 2 + 2.
  Eigen::MatrixXd cost(2, 2);
  cost << 1, 2, 2, 10;
  EXPECT_EQ(SolveAssignment(cost, 20.0), (std::vector<int>{1, 0}));
}

TEST(AssignmentTest, GateAndEmpty) {
  Eigen::MatrixXd cost(2, 3);
  cost << 25, 30, 5, 21, 22, std::numeric_limits<double>::infinity();
  EXPECT_EQ(SolveAssignment(cost, 20.0), (std::vector<int>{2, -1}));
  EXPECT_TRUE(SolveAssignment(Eigen::MatrixXd(0, 4), 20.0).empty());
  EXPECT_EQ(SolveAssignment(Eigen::MatrixXd(3, 0), 20.0), (std::vector<int>{-1, -1, -1}));
}

}  // namespace
}  // namespace mocap

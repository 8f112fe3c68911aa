// Sorted greedy versus optimal assignment, and gates.
#include "track/assignment.h"

#include <gtest/gtest.h>

namespace mocap {
namespace {

TEST(Assignment, GreedyTakesCheapestPairFirstOptimalMinimisesTotal) {
  // Greedy takes (0,0)=1 and then must give row 1 column 1 = 10; optimal: 2 + 3.
  Eigen::MatrixXd cost(2, 2);
  cost << 1, 2, 3, 10;
  const std::vector<double> gates(2, 20.0);
  EXPECT_EQ(AssignGreedySorted(cost, gates), (std::vector<int>{0, 1}));
  EXPECT_EQ(AssignOptimal(cost, gates), (std::vector<int>{1, 0}));
}

TEST(Assignment, GatesForbidPairs) {
  Eigen::MatrixXd cost(2, 3);
  cost << 5, 1, 9, 2, 8, 30;
  const std::vector<double> gates = {4.0, 4.0};
  EXPECT_EQ(AssignGreedySorted(cost, gates), (std::vector<int>{1, 0}));
  EXPECT_EQ(AssignOptimal(cost, gates), (std::vector<int>{1, 0}));
  const std::vector<double> tight = {0.5, 4.0};
  EXPECT_EQ(AssignGreedySorted(cost, tight), (std::vector<int>{-1, 0}));
  EXPECT_EQ(AssignOptimal(cost, tight), (std::vector<int>{-1, 0}));
}

TEST(Assignment, OptimalMaximisesPairsWithinGate) {
  // Greedy pairs row 0 with column 0 and strands row 1; optimal pairs both.
  Eigen::MatrixXd cost(2, 2);
  cost << 1, 3, 2, 50;
  const std::vector<double> gates(2, 10.0);
  EXPECT_EQ(AssignGreedySorted(cost, gates), (std::vector<int>{0, -1}));
  EXPECT_EQ(AssignOptimal(cost, gates), (std::vector<int>{1, 0}));
  EXPECT_EQ(AssignmentMethodFromString(AssignmentMethodToString(AssignmentMethod::kGreedy)),
            AssignmentMethod::kGreedy);
  EXPECT_THROW(AssignmentMethodFromString("random"), std::invalid_argument);
}

TEST(Assignment, EmptyInputGivesNoPairs) {
  // No predictions, or no measurements: nothing to pair, and nothing read out of bounds.
  const Eigen::MatrixXd no_rows(0, 3);
  EXPECT_TRUE(AssignGreedySorted(no_rows, {}).empty());
  EXPECT_TRUE(AssignOptimal(no_rows, {}).empty());
  const Eigen::MatrixXd no_columns(2, 0);
  const std::vector<double> gates(2, 1.0);
  EXPECT_EQ(AssignGreedySorted(no_columns, gates), (std::vector<int>{-1, -1}));
  EXPECT_EQ(AssignOptimal(no_columns, gates), (std::vector<int>{-1, -1}));
}

TEST(Assignment, GateCountMustMatchRows) {
  Eigen::MatrixXd cost(2, 2);
  cost << 1, 2, 3, 4;
  for (const std::vector<double>& gates : {std::vector<double>{}, std::vector<double>{5.0}}) {
    EXPECT_THROW(AssignGreedySorted(cost, gates), std::invalid_argument);
    EXPECT_THROW(AssignOptimal(cost, gates), std::invalid_argument);
    EXPECT_THROW(Assign(AssignmentMethod::kOptimal, cost, gates), std::invalid_argument);
  }
}

}  // namespace
}  // namespace mocap

// Hungarian method with row/column potentials, one shortest augmenting path per row.
#include "util/assignment.h"

#include <cmath>
#include <limits>

namespace mocap {
namespace {

// Rows <= columns; every row gets a column. Returns column of each row.
std::vector<int> SolveTall(const Eigen::MatrixXd& cost) {
  const int rows = static_cast<int>(cost.rows());
  const int cols = static_cast<int>(cost.cols());
  const double inf = std::numeric_limits<double>::infinity();
  // 1-based with a virtual column 0 that holds the row being inserted.
  std::vector<double> row_potential(rows + 1, 0.0), col_potential(cols + 1, 0.0);
  std::vector<int> row_of_col(cols + 1, 0), previous_col(cols + 1, 0);
  for (int row = 1; row <= rows; ++row) {
    row_of_col[0] = row;
    int col = 0;
    std::vector<double> min_slack(cols + 1, inf);
    std::vector<char> used(cols + 1, 0);
    do {
      used[col] = 1;
      const int current_row = row_of_col[col];
      double delta = inf;
      int next_col = 0;
      for (int c = 1; c <= cols; ++c) {
        if (used[c]) continue;
        const double slack = cost(current_row - 1, c - 1) - row_potential[current_row] - col_potential[c];
        if (slack < min_slack[c]) {
          min_slack[c] = slack;
          previous_col[c] = col;
        }
        if (min_slack[c] < delta) {
          delta = min_slack[c];
          next_col = c;
        }
      }
      for (int c = 0; c <= cols; ++c) {
        if (used[c]) {
          row_potential[row_of_col[c]] += delta;
          col_potential[c] -= delta;
        } else {
          min_slack[c] -= delta;
        }
      }
      col = next_col;
    } while (row_of_col[col] != 0);
    // Flip the augmenting path back to the virtual column.
    do {
      const int prev = previous_col[col];
      row_of_col[col] = row_of_col[prev];
      col = prev;
    } while (col != 0);
  }
  std::vector<int> col_of_row(rows, -1);
  for (int c = 1; c <= cols; ++c) {
    if (row_of_col[c] != 0) col_of_row[row_of_col[c] - 1] = c - 1;
  }
  return col_of_row;
}

}  // namespace

std::vector<int> SolveAssignment(const Eigen::MatrixXd& cost, double gate) {
  const Eigen::Index rows = cost.rows();
  const Eigen::Index cols = cost.cols();
  std::vector<int> result(rows, -1);
  if (rows == 0 || cols == 0) return result;
  // A forbidden pair costs more than any complete set of allowed pairs, so the optimum first
  // uses as few forbidden pairs as possible (most matches) and then the least total cost.
  const double forbidden = (gate > 0.0 ? gate : 1.0) * (static_cast<double>(std::min(rows, cols)) + 1.0) * 2.0;
  const bool transpose = rows > cols;
  Eigen::MatrixXd tall(transpose ? cols : rows, transpose ? rows : cols);
  for (Eigen::Index r = 0; r < rows; ++r) {
    for (Eigen::Index c = 0; c < cols; ++c) {
      const double value = cost(r, c);
      const double entry = (std::isfinite(value) && value <= gate) ? value : forbidden;
      if (transpose) {
        tall(c, r) = entry;
      } else {
        tall(r, c) = entry;
      }
    }
  }
  const std::vector<int> assigned = SolveTall(tall);
  for (size_t i = 0; i < assigned.size(); ++i) {
    const int j = assigned[i];
    if (j < 0 || tall(static_cast<Eigen::Index>(i), j) >= forbidden) continue;
    if (transpose) {
      result[j] = static_cast<int>(i);
    } else {
      result[i] = j;
    }
  }
  return result;
}

}  // namespace mocap

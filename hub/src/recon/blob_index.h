// Per-camera grid of one frame's observations for "nearest blob to this image point within r"
// queries (prediction search, view completion, the ghost filter): O(cells touched + blobs in
// them), independent of how many blobs the image holds elsewhere.
#pragma once

#include <algorithm>
#include <vector>

#include <Eigen/Core>

#include "recon/frame_views.h"
#include "recon/matcher.h"

namespace mocap {

class BlobIndex {
 public:
  // Smallest cell edge in pixels: gates and residual limits are a few pixels, so a query reads
  // a few cells whatever the number of blobs (a subject's blobs crowd one part of an image).
  static constexpr double kCellPx = 12.0;
  // Cells per blob at most (cells grow when few blobs spread over a large image): fine enough
  // that a crowded subject's blobs mostly sit one to a cell, so a query compares few of them.
  // A build touches only the cells that hold blobs, so empty cells cost nothing to build.
  static constexpr double kCellsPerBlob = 16.0;

  void Build(const RigModel& rig, const FrameViews& views);
  // Builds camera c's grid only: cameras are independent, so several threads may build
  // different cameras of one index after Resize.
  void Resize(const RigModel& rig);
  void BuildCamera(const RigModel& rig, const FrameViews& views, int camera);
  // Nearest observation of `camera` to `normalized` within `radius` (normalized units) that
  // `available` accepts, or -1.
  template <typename Accept>
  int Nearest(const FrameViews& views, int camera, const Eigen::Vector2d& normalized, double radius,
              Accept available) const;
  // Calls visit(observation, distance) for every observation of `camera` within `radius`.
  template <typename Visit>
  void ForEachWithin(const FrameViews& views, int camera, const Eigen::Vector2d& normalized, double radius,
                     Visit visit) const;

 private:
  struct Entry {
    Eigen::Vector2d normalized;
    int observation;
    int cell;  // its cell's number: a cell's entries run while it is the same
  };
  // A cell of the current build holds the entries from `begin` on that carry its number; a cell
  // whose stamp is not the grid's holds none (it was filled by an earlier build, or never), so a
  // build writes only the cells its blobs fall in and never clears the others (at 64 cameras
  // clearing every cell cost more than the blobs). Eight bytes: a frame's searches and build
  // touch cells all over the grids, and half the size is half the lines to fetch.
  struct Cell {
    unsigned stamp = 0;
    int begin = 0;  // Build's count of its blobs until the range is placed
  };
  // One camera's observations bucketed into square cells (row-major cell numbers).
  struct Grid {
    double min_x = 0.0, min_y = 0.0, inverse_cell = 1.0;
    int cols = 0, rows = 0;
    unsigned stamp = 0;  // of the current build
    std::vector<Cell> cells;
    std::vector<Entry> entries;  // and one more, of cell -1, that ends the last range
    // Scratch of Build, per camera so cameras build in parallel: each blob's cell, and its rank
    // among the blobs of that cell.
    std::vector<std::pair<int, int>> cell_and_rank;
  };
  // Calls visit(entry) for the entries of the cells the square around `at` touches.
  template <typename Visit>
  static void ForEachCandidate(const Grid& grid, const Eigen::Vector2d& at, double radius, Visit visit);

  std::vector<Grid> grids_;
};

template <typename Visit>
void BlobIndex::ForEachCandidate(const Grid& grid, const Eigen::Vector2d& at, double radius, Visit visit) {
  if (grid.entries.size() < 2) return;
  // Cell coordinates of the square's corners, clamped to the grid (a point off the grid still
  // reaches blobs within the radius on its edge).
  const double x0 = (at.x() - radius - grid.min_x) * grid.inverse_cell;
  const double x1 = (at.x() + radius - grid.min_x) * grid.inverse_cell;
  const double y0 = (at.y() - radius - grid.min_y) * grid.inverse_cell;
  const double y1 = (at.y() + radius - grid.min_y) * grid.inverse_cell;
  if (!(x1 >= 0.0 && y1 >= 0.0 && x0 < grid.cols && y0 < grid.rows)) return;
  const int c0 = std::max(0, static_cast<int>(x0)), c1 = std::min(grid.cols - 1, static_cast<int>(x1));
  const int r0 = std::max(0, static_cast<int>(y0)), r1 = std::min(grid.rows - 1, static_cast<int>(y1));
  for (int r = r0; r <= r1; ++r) {
    for (int k = r * grid.cols + c0, last = r * grid.cols + c1; k <= last; ++k) {
      const Cell& cell = grid.cells[k];
      if (cell.stamp != grid.stamp) continue;
      for (const Entry* entry = grid.entries.data() + cell.begin; entry->cell == k; ++entry) visit(*entry);
    }
  }
}

template <typename Accept>
int BlobIndex::Nearest(const FrameViews&, int camera, const Eigen::Vector2d& normalized, double radius,
                       Accept available) const {
  int best = -1;
  double best_distance = radius * radius;
  ForEachCandidate(grids_[camera], normalized, radius, [&](const Entry& entry) {
    const double d2 = (entry.normalized - normalized).squaredNorm();
    // Ties go to the lower observation index, so the answer does not depend on cell order.
    if ((d2 < best_distance || (d2 == best_distance && (best < 0 || entry.observation < best))) &&
        available(entry.observation)) {
      best_distance = d2;
      best = entry.observation;
    }
  });
  return best;
}

template <typename Visit>
void BlobIndex::ForEachWithin(const FrameViews&, int camera, const Eigen::Vector2d& normalized, double radius,
                              Visit visit) const {
  ForEachCandidate(grids_[camera], normalized, radius, [&](const Entry& entry) {
    const double distance = (entry.normalized - normalized).norm();
    if (distance <= radius) visit(entry.observation, distance);
  });
}

// Adds to the point every camera's available observation that lies within the triangulation's
// residual limit of its reprojection and is not yet a view, then re-solves. A marker partly
// gathered (prediction gates are small in some views) would otherwise leave blobs from which
// the matcher builds a duplicate. Blobs `shared` marks (may be null) are solved as
// TriangulateRobust does. Every observation it considered is appended to *picked when given
// (whether the joint solve kept it or not).
void CompleteViews(const RigModel& rig, const FrameViews& views, const BlobIndex& index,
                   const UseCounts& used, const TriangulationOptions& options, TriangulatedPoint* point,
                   const std::vector<char>* shared = nullptr, std::vector<int>* picked = nullptr);

}  // namespace mocap

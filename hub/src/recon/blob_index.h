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
  // that a query's runs are short, coarse enough that the build's running sum over every cell
  // stays cheap (of 4, 6, 8 and 16, 8 made 16 x 60 and 64 x 100 fastest).
  static constexpr double kCellsPerBlob = 8.0;

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
  // Nearest(views, camera, normalized, radius, accept every observation), comparing a short run
  // of blobs in full instead of branching on how many it holds and which is nearer: the
  // prediction search asks this of every prediction in every camera, and those branches went
  // every which way.
  int NearestOfAll(int camera, const Eigen::Vector2d& normalized, double radius) const;
  // Calls visit(observation, distance) for every observation of `camera` within `radius`.
  template <typename Visit>
  void ForEachWithin(const FrameViews& views, int camera, const Eigen::Vector2d& normalized, double radius,
                     Visit visit) const;

 private:
  struct Entry {
    Eigen::Vector2d normalized;
    int observation;
  };
  // One camera's observations bucketed into square cells, stored cell after cell in row-major
  // order: a row's cells from c0 to c1 are one run of entries, [begin[r * cols + c0],
  // begin[r * cols + c1 + 1]), so a query walks one run per row instead of cell by cell.
  struct Grid {
    double min_x = 0.0, min_y = 0.0, inverse_cell = 1.0;
    int cols = 0, rows = 0;
    std::vector<int> begin;  // rows * cols + 1: cell k's entries are [begin[k], begin[k + 1])
    std::vector<Entry> entries;  // then kWindow entries at infinity, read past the last run
    std::vector<int> cell_of;  // Build's scratch, per camera so cameras build in parallel
  };
  // A run of entries of up to this many is compared in full, without a branch on its length.
  static constexpr int kWindow = 4;
  // The cells the square around `at` touches, clamped to the grid (a point off the grid still
  // reaches blobs within the radius on its edge); false when it touches none.
  struct CellRange {
    int c0, c1, r0, r1;
  };
  static bool TouchedCells(const Grid& grid, const Eigen::Vector2d& at, double radius, CellRange* range);
  // Calls visit(entry) for the entries of the cells the square around `at` touches.
  template <typename Visit>
  static void ForEachCandidate(const Grid& grid, const Eigen::Vector2d& at, double radius, Visit visit);

  std::vector<Grid> grids_;
};

inline bool BlobIndex::TouchedCells(const Grid& grid, const Eigen::Vector2d& at, double radius, CellRange* range) {
  // A negative or NaN radius reaches nothing.
  if (grid.rows == 0 || !(radius >= 0.0)) return false;
  const double x0 = (at.x() - radius - grid.min_x) * grid.inverse_cell;
  const double x1 = (at.x() + radius - grid.min_x) * grid.inverse_cell;
  const double y0 = (at.y() - radius - grid.min_y) * grid.inverse_cell;
  const double y1 = (at.y() + radius - grid.min_y) * grid.inverse_cell;
  if (!(x1 >= 0.0 && y1 >= 0.0 && x0 < grid.cols && y0 < grid.rows)) return false;
  // Clamped before the conversion: a huge (or infinite) radius gives corners far outside what an
  // int holds.
  range->c0 = static_cast<int>(std::max(0.0, x0));
  range->c1 = static_cast<int>(std::min(grid.cols - 1.0, x1));
  range->r0 = static_cast<int>(std::max(0.0, y0));
  range->r1 = static_cast<int>(std::min(grid.rows - 1.0, y1));
  return true;
}

template <typename Visit>
void BlobIndex::ForEachCandidate(const Grid& grid, const Eigen::Vector2d& at, double radius, Visit visit) {
  CellRange range;
  if (!TouchedCells(grid, at, radius, &range)) return;
  const Entry* entries = grid.entries.data();
  for (int r = range.r0; r <= range.r1; ++r) {
    const int* row = grid.begin.data() + r * grid.cols;
    for (const Entry *entry = entries + row[range.c0], *end = entries + row[range.c1 + 1]; entry != end; ++entry) {
      visit(*entry);
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

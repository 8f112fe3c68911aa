// Blob index and view completion.
#include "recon/blob_index.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "util/counting_sort.h"

namespace mocap {

void BlobIndex::Resize(const RigModel& rig) { grids_.resize(rig.NumCameras()); }

void BlobIndex::BuildCamera(const RigModel& rig, const FrameViews& views, int camera) {
  Grid& grid = grids_[camera];
  const int begin = views.camera_begin[camera], end = views.camera_begin[camera + 1];
  const int count = end - begin;
  grid.entries.resize(static_cast<size_t>(count) + kWindow);
  constexpr double kFar = std::numeric_limits<double>::infinity();
  std::fill(grid.entries.begin() + count, grid.entries.end(), Entry{Eigen::Vector2d(kFar, kFar), -1});
  if (count == 0) {
    grid.cols = grid.rows = 0;
    return;
  }
  Eigen::Vector2d low = views.observations[begin].normalized, high = low;
  for (int o = begin + 1; o < end; ++o) {
    low = low.cwiseMin(views.observations[o].normalized);
    high = high.cwiseMax(views.observations[o].normalized);
  }
  // Blobs lie in the image, so the grid spans at most the image; the cap only bounds memory
  // against a rig file with a nonsensical focal length.
  constexpr int kMaxCellsPerSide = 512;
  const Eigen::Vector2d span = high - low;
  double cell = kCellPx / rig.camera(camera).focal_px;
  cell = std::max(cell, span.maxCoeff() / (kMaxCellsPerSide - 1));
  cell = std::max(cell, std::sqrt(span.x() * span.y() / (kCellsPerBlob * count)));
  if (!(cell > 0.0)) cell = 1.0;  // one blob, or all at one spot
  grid.min_x = low.x();
  grid.min_y = low.y();
  grid.inverse_cell = 1.0 / cell;
  grid.cols = static_cast<int>((high.x() - low.x()) * grid.inverse_cell) + 1;
  grid.rows = static_cast<int>((high.y() - low.y()) * grid.inverse_cell) + 1;
  const int cells = grid.cols * grid.rows;
  // Grouped by cell, observations in their order within a cell.
  grid.cell_of.resize(count);
  for (int o = begin; o < end; ++o) {
    const Eigen::Vector2d& p = views.observations[o].normalized;
    const int col = std::min(grid.cols - 1, static_cast<int>((p.x() - grid.min_x) * grid.inverse_cell));
    const int row = std::min(grid.rows - 1, static_cast<int>((p.y() - grid.min_y) * grid.inverse_cell));
    grid.cell_of[o - begin] = row * grid.cols + col;
  }
  CountingSort(
      count, cells, [&](int i) { return grid.cell_of[i]; }, &grid.begin,
      [&](int i, int slot) { grid.entries[slot] = {views.observations[begin + i].normalized, begin + i}; });
}

int BlobIndex::NearestOfAll(int camera, const Eigen::Vector2d& normalized, double radius) const {
  const Grid& grid = grids_[camera];
  CellRange range;
  if (!TouchedCells(grid, normalized, radius, &range)) return -1;
  // Observations compared unsigned: "none" (-1) is then above every observation, and a tie at the
  // radius goes to the blob as Nearest's does. Selects, not branches.
  unsigned best = ~0u;
  double best_distance = radius * radius;
  const auto consider = [&](const Entry& entry) {
    const double d2 = (entry.normalized - normalized).squaredNorm();
    const unsigned observation = static_cast<unsigned>(entry.observation);
    const bool nearer = (d2 < best_distance) | ((d2 == best_distance) & (observation < best));
    best_distance = nearer ? d2 : best_distance;
    best = nearer ? observation : best;
  };
  // A short run is compared kWindow entries long: those past it are other cells' blobs (or the
  // sentinels at infinity), and any of them within the radius lies in a touched cell anyway, so
  // meeting it changes nothing; nor does meeting a blob twice. (Up to rounding: a blob exactly at
  // the radius whose cell the rounded square just misses is then found, as a scan of every blob
  // finds it, where Nearest's walk over the cells does not.)
  const Entry* entries = grid.entries.data();
  const auto scan_row = [&](int r) {
    const int* row = grid.begin.data() + r * grid.cols;
    const Entry* entry = entries + row[range.c0];
    const Entry* end = entries + row[range.c1 + 1];
    if (end - entry <= kWindow) {
      for (int i = 0; i < kWindow; ++i) consider(entry[i]);
    } else {
      for (; entry != end; ++entry) consider(*entry);
    }
  };
  for (int r = range.r0; r <= range.r1; ++r) scan_row(r);
  return static_cast<int>(best);
}

void BlobIndex::Build(const RigModel& rig, const FrameViews& views) {
  Resize(rig);
  for (int c = 0; c < rig.NumCameras(); ++c) BuildCamera(rig, views, c);
}

void CompleteViews(const RigModel& rig, const FrameViews& views, const BlobIndex& index,
                   const UseCounts& used, const TriangulationOptions& options, TriangulatedPoint* point,
                   const std::vector<char>* shared, std::vector<int>* picked) {
  const int num_cameras = rig.NumCameras();
  // Per-thread scratch: called for every point of every frame.
  thread_local std::vector<char> has_camera;
  thread_local std::vector<int> extended;
  thread_local TriangulatedPoint completed;
  has_camera.assign(num_cameras, 0);
  for (int o : point->observations) has_camera[views.observations[o].camera] = 1;
  extended = point->observations;
  for (int c = 0; c < num_cameras; ++c) {
    if (has_camera[c]) continue;
    const CameraModel& cam = rig.camera(c);
    const Eigen::Vector3d p = cam.cam_from_world_rotation * point->point_in_world + cam.cam_from_world_translation;
    if (!(p.z() > options.min_depth_mm)) continue;
    const int found = index.Nearest(views, c, p.head<2>() / p.z(), options.max_reprojection_px / cam.focal_px,
                                    [&](int o) { return IsAvailable(views.observations[o], used[o]); });
    if (found >= 0) extended.push_back(found);
  }
  if (picked != nullptr) picked->insert(picked->end(), extended.begin() + point->observations.size(), extended.end());
  if (extended.size() == point->observations.size()) return;
  // The extra views were chosen within the residual limit; if the joint solve disagrees, the
  // original point stands.
  if (TriangulateRobust(rig, views, extended, options, &completed, shared) &&
      completed.observations.size() > point->observations.size()) {
    completed.rejected.insert(completed.rejected.begin(), point->rejected.begin(), point->rejected.end());
    std::swap(*point, completed);
  }
}

}  // namespace mocap

// Blob index and view completion.
#include "recon/blob_index.h"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace mocap {

void BlobIndex::Resize(const RigModel& rig) { grids_.resize(rig.NumCameras()); }

void BlobIndex::BuildCamera(const RigModel& rig, const FrameViews& views, int camera) {
  Grid& grid = grids_[camera];
  const int begin = views.camera_begin[camera], end = views.camera_begin[camera + 1];
  const int count = end - begin;
  grid.entries.resize(count + 1);
  grid.entries[count].cell = -1;
  if (count == 0) return;
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
  const size_t cells = static_cast<size_t>(grid.cols) * grid.rows;
  // Counting sort into cells; within a cell, observations keep their order. A new stamp makes
  // every cell of earlier builds empty; a stamp that wraps around clears them for real.
  if (++grid.stamp == 0) {
    for (Cell& stale : grid.cells) stale.stamp = 0;
    grid.stamp = 1;
  }
  if (grid.cells.size() < cells) grid.cells.resize(cells);
  grid.cell_and_rank.resize(count);
  for (int o = begin; o < end; ++o) {
    const Eigen::Vector2d& p = views.observations[o].normalized;
    const int col = std::min(grid.cols - 1, static_cast<int>((p.x() - grid.min_x) * grid.inverse_cell));
    const int row = std::min(grid.rows - 1, static_cast<int>((p.y() - grid.min_y) * grid.inverse_cell));
    const int k = row * grid.cols + col;
    Cell& cell = grid.cells[k];
    if (cell.stamp != grid.stamp) cell = {grid.stamp, 0};
    grid.cell_and_rank[o - begin] = {k, cell.begin++};
  }
  // Ranges in the order cells are first met (at their blob of rank 0, which holds the count
  // until then), each blob placed at its rank in its cell's range.
  int next = 0;
  for (int i = 0; i < count; ++i) {
    const auto [k, rank] = grid.cell_and_rank[i];
    Cell& cell = grid.cells[k];
    if (rank == 0) {
      const int blobs = cell.begin;
      cell.begin = next;
      next += blobs;
    }
    grid.entries[cell.begin + rank] = {views.observations[begin + i].normalized, begin + i, k};
  }
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

// Live wand coverage per camera (see wand_coverage.h).
#include "calib/wand_coverage.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>

namespace mocap {

void WandCoverageOptions::Check() const {
  if (columns < 1 || columns > 64 || rows < 1 || rows > 64)
    throw std::invalid_argument("the coverage grid must have 1..64 columns and rows");
  if (cell_samples < 1 || cell_samples > 100000) throw std::invalid_argument("cell samples must be 1..100000");
  if (!(min_blob_separation_px >= 0.0 && min_blob_separation_px < 1000.0))
    throw std::invalid_argument("the blob separation must be within [0, 1000) px");
  if (min_views_per_frame < 1) throw std::invalid_argument("views per frame must be >= 1");
}

double CameraCoverage::Share(int cell_samples) const {
  if (counts.empty()) return 0.0;
  size_t covered = 0;
  for (uint32_t c : counts) covered += c >= static_cast<uint32_t>(cell_samples);
  return static_cast<double>(covered) / static_cast<double>(counts.size());
}

WandCoverage::WandCoverage(const Rig& rig, size_t wand_markers, const WandCoverageOptions& options)
    : options_(options), markers_(wand_markers) {
  options_.Check();
  if (wand_markers < 1 || wand_markers > 3)
    throw std::invalid_argument("a wand has 2 or 3 markers (1: a single marker waved)");
  for (const Camera& c : rig.cameras) {
    CameraCoverage coverage;
    coverage.id = c.id;
    coverage.width = c.intrinsics.width;
    coverage.height = c.intrinsics.height;
    coverage.counts.assign(static_cast<size_t>(options_.columns * options_.rows), 0);
    cameras_.push_back(std::move(coverage));
  }
}

bool WandCoverage::IsWandView(const CameraFrame& frame, size_t camera) const {
  if (frame.blobs.size() != markers_) return false;
  const CameraCoverage& c = cameras_[camera];
  for (size_t i = 0; i < frame.blobs.size(); ++i) {
    const Blob& b = frame.blobs[i];
    if (b.flags & kBlobMerged) return false;
    if (!(b.pixel.x() >= 0.0 && b.pixel.x() < c.width && b.pixel.y() >= 0.0 && b.pixel.y() < c.height)) return false;
    for (size_t j = i + 1; j < frame.blobs.size(); ++j)
      if ((b.pixel - frame.blobs[j].pixel).norm() < options_.min_blob_separation_px) return false;
  }
  return true;
}

bool WandCoverage::Add(const FrameSet& set) {
  ++frame_sets_;
  std::vector<std::pair<size_t, const CameraFrame*>> views;
  for (const CameraFrame& frame : set.cameras) {
    for (size_t i = 0; i < cameras_.size(); ++i) {
      if (cameras_[i].id == frame.camera_id) {
        if (IsWandView(frame, i)) views.emplace_back(i, &frame);
        break;
      }
    }
  }
  if (views.size() < static_cast<size_t>(options_.min_views_per_frame)) return false;
  ++wand_frames_;
  for (const auto& [i, frame] : views) {
    CameraCoverage& c = cameras_[i];
    ++c.samples;
    for (const Blob& b : frame->blobs) {
      const int column = std::clamp(static_cast<int>(b.pixel.x() * options_.columns / c.width), 0, options_.columns - 1);
      const int row = std::clamp(static_cast<int>(b.pixel.y() * options_.rows / c.height), 0, options_.rows - 1);
      ++c.counts[static_cast<size_t>(row * options_.columns + column)];
    }
  }
  return true;
}

namespace {

// Thirds of the image, h from the left and v from the top (0..2).
int Third(int cell, int cells) { return std::clamp(cell * 3 / std::max(cells, 1), 0, 2); }

std::string RegionName(int h, int v) {
  static const char* const kVertical[3] = {"top", "", "bottom"};
  static const char* const kHorizontal[3] = {"left", "", "right"};
  if (h == 1 && v == 1) return "centre";
  if (h == 1) return kVertical[v];
  if (v == 1) return kHorizontal[h];
  return std::string(kVertical[v]) + " " + kHorizontal[h];
}

}  // namespace

std::string ImageRegionName(int column, int row, int columns, int rows) {
  return RegionName(Third(column, columns), Third(row, rows));
}

CoverageAdvice WandCoverage::Advise(size_t index, size_t min_samples, double coverage_target) const {
  const CameraCoverage& c = cameras_.at(index);
  CoverageAdvice advice;
  const double share = c.Share(options_.cell_samples);
  char figures[96];
  // The share rounded down, so that a camera short of its target never reads as having reached it.
  std::snprintf(figures, sizeof(figures), "coverage %.0f %% of %.0f %%, %zu/%zu samples", std::floor(100.0 * share),
                100.0 * coverage_target, c.samples, min_samples);
  const std::string camera = "camera " + std::to_string(c.id) + ": ";
  if (c.samples >= min_samples && share >= coverage_target) {
    advice.enough = true;
    advice.text = camera + "enough (" + figures + ")";
    return advice;
  }
  if (c.samples == 0) {
    advice.text = camera + "has not seen the wand alone yet: wave it inside this camera's view, away from other "
                           "bright spots (" + figures + ")";
    return advice;
  }
  // The emptiest of the nine regions: the fewest covered cells relative to its size, then the
  // fewest sightings.
  double best_fill = std::numeric_limits<double>::infinity();
  double best_count = std::numeric_limits<double>::infinity();
  for (int v = 0; v < 3; ++v) {
    for (int h = 0; h < 3; ++h) {
      size_t cells = 0, covered = 0;
      double count = 0.0;
      for (int row = 0; row < options_.rows; ++row) {
        for (int column = 0; column < options_.columns; ++column) {
          if (Third(column, options_.columns) != h || Third(row, options_.rows) != v)
            continue;
          const uint32_t n = c.counts[static_cast<size_t>(row * options_.columns + column)];
          ++cells;
          covered += n >= static_cast<uint32_t>(options_.cell_samples);
          count += n;
        }
      }
      if (cells == 0) continue;
      const double fill = static_cast<double>(covered) / static_cast<double>(cells);
      const double mean = count / static_cast<double>(cells);
      if (fill < best_fill || (fill == best_fill && mean < best_count)) {
        best_fill = fill;
        best_count = mean;
        advice.region = RegionName(h, v);
      }
    }
  }
  if (share >= coverage_target) {
    advice.text = camera + "covered; keep waving for more samples (" + figures + ")";
  } else {
    advice.text = camera + "wave towards the " + advice.region + " (" + figures + ")";
  }
  return advice;
}

}  // namespace mocap

// Wand frame selection: a static-reflection mask per camera (a coarse grid of blob positions
// counted once per frame), then views with exactly the wand's blob count, well separated, and
// for three markers collinear with the middle one between the ends.
#include "calib/wand_observations.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <unordered_map>
#include <unordered_set>

namespace mocap {
namespace {

int64_t CellKey(const Eigen::Vector2d& pixel, double cell) {
  const int64_t x = static_cast<int64_t>(std::floor(pixel.x() / cell));
  const int64_t y = static_cast<int64_t>(std::floor(pixel.y() / cell));
  return (x << 32) ^ (y & 0xffffffff);
}

// Cells that hold a blob in at least min_fraction of the camera's frames.
class StaticMask {
 public:
  StaticMask(double radius_px) : cell_(std::max(radius_px, 0.5)) {}

  void Count(const std::vector<Blob>& blobs) {
    std::unordered_set<int64_t> seen;
    for (const Blob& blob : blobs) seen.insert(CellKey(blob.pixel, cell_));
    for (int64_t key : seen) ++counts_[key];
    ++frames_;
  }

  void Finish(double min_fraction) {
    const double needed = std::max(10.0, min_fraction * static_cast<double>(frames_));
    for (const auto& [key, count] : counts_) {
      if (static_cast<double>(count) >= needed) static_cells_.insert(key);
    }
    counts_.clear();
  }

  // A blob straddling a cell edge lands in a neighbour cell, so neighbours count too.
  bool IsStatic(const Eigen::Vector2d& pixel) const {
    if (static_cells_.empty()) return false;
    for (int dx = -1; dx <= 1; ++dx) {
      for (int dy = -1; dy <= 1; ++dy) {
        const Eigen::Vector2d shifted = pixel + Eigen::Vector2d(dx * cell_, dy * cell_);
        if (static_cells_.count(CellKey(shifted, cell_)) != 0) return true;
      }
    }
    return false;
  }

 private:
  double cell_;
  std::unordered_map<int64_t, int> counts_;
  std::unordered_set<int64_t> static_cells_;
  int frames_ = 0;
};

// Orders the blobs of one view along the wand; false when they do not look like the wand.
bool OrderAlongWand(std::vector<Eigen::Vector2d>* pixels, const WandSelectionOptions& options) {
  std::vector<Eigen::Vector2d>& p = *pixels;
  for (size_t i = 0; i < p.size(); ++i) {
    for (size_t j = i + 1; j < p.size(); ++j) {
      if ((p[i] - p[j]).norm() < options.min_blob_separation_px) return false;
    }
  }
  if (p.size() < 3) return true;  // one marker or the two ends: nothing to order
  // Three blobs: the ends are the farthest pair; the middle must lie between them on the line.
  size_t a = 0, b = 1;
  double best = -1.0;
  for (size_t i = 0; i < 3; ++i) {
    for (size_t j = i + 1; j < 3; ++j) {
      const double d = (p[i] - p[j]).norm();
      if (d > best) {
        best = d;
        a = i;
        b = j;
      }
    }
  }
  const size_t m = 3 - a - b;
  const Eigen::Vector2d axis = (p[b] - p[a]) / best;
  const Eigen::Vector2d rel = p[m] - p[a];
  const double across = std::abs(axis.x() * rel.y() - axis.y() * rel.x());
  if (across > options.max_middle_offset_fraction * best) return false;
  p = {p[a], p[m], p[b]};
  return true;
}

}  // namespace

WandGeometry WandGeometry::TwoMarker(double length_mm) {
  WandGeometry wand;
  wand.marker_offsets_mm = {-0.5 * length_mm, 0.5 * length_mm};
  return wand;
}

WandGeometry WandGeometry::SingleMarker() {
  WandGeometry wand;
  wand.marker_offsets_mm = {0.0};
  return wand;
}

WandGeometry WandGeometry::ThreeMarker(double length_mm, double middle_from_first_mm) {
  WandGeometry wand;
  wand.marker_offsets_mm = {-0.5 * length_mm, -0.5 * length_mm + middle_from_first_mm, 0.5 * length_mm};
  return wand;
}

void WandGeometry::Check() const {
  const size_t n = marker_offsets_mm.size();
  if (n == 1 && marker_offsets_mm[0] == 0.0) return;  // a single marker
  if (n != 2 && n != 3) throw std::invalid_argument("a wand has 2 or 3 markers");
  if (!(LengthMm() > 10.0)) throw std::invalid_argument("wand length must be > 10 mm");
  if (std::abs(marker_offsets_mm.front() + marker_offsets_mm.back()) > 1e-9) {
    throw std::invalid_argument("wand offsets must be measured from the midpoint of its ends");
  }
  if (n == 3) {
    const double middle = marker_offsets_mm[1] - marker_offsets_mm[0];
    const double length = LengthMm();
    if (!(middle > 0.1 * length && middle < 0.9 * length)) {
      throw std::invalid_argument("the middle marker must lie between 10% and 90% of the wand length");
    }
    // A centred middle marker makes both ends look alike, so their order could never be known.
    if (std::abs(middle - 0.5 * length) < 0.05 * length) {
      throw std::invalid_argument("the middle marker must be off-centre (at least 5% of the length)");
    }
  }
}

void WandSelectionOptions::Check() const {
  if (!(static_min_fraction > 0.0 && static_min_fraction <= 1.0)) {
    throw std::invalid_argument("static_min_fraction must be in (0, 1]");
  }
  if (!(static_radius_px > 0.0)) throw std::invalid_argument("static_radius_px must be > 0");
  if (!(min_blob_separation_px >= 0.0)) throw std::invalid_argument("min_blob_separation_px must be >= 0");
  if (!(max_middle_offset_fraction > 0.0)) throw std::invalid_argument("max_middle_offset_fraction must be > 0");
  if (min_views_per_frame < 2) throw std::invalid_argument("min_views_per_frame must be >= 2");
}

void WandView::SwapEnds() {
  std::reverse(pixels.begin(), pixels.end());
  std::reverse(normalized.begin(), normalized.end());
}

std::vector<WandFrame> SelectWandFrames(const std::vector<FrameSet>& frames, const Rig& rig,
                                        const WandGeometry& wand, const WandSelectionOptions& options,
                                        WandSelectionStats* stats) {
  wand.Check();
  options.Check();
  const size_t n_cameras = rig.cameras.size();
  std::unordered_map<uint32_t, size_t> index_of;
  for (size_t i = 0; i < n_cameras; ++i) index_of[rig.cameras[i].id] = i;

  std::vector<StaticMask> masks(n_cameras, StaticMask(options.static_radius_px));
  for (const FrameSet& set : frames) {
    for (const CameraFrame& frame : set.cameras) {
      const auto it = index_of.find(frame.camera_id);
      if (it != index_of.end()) masks[it->second].Count(frame.blobs);
    }
  }
  for (StaticMask& mask : masks) mask.Finish(options.static_min_fraction);

  WandSelectionStats local;
  local.static_blobs_masked.assign(n_cameras, 0);
  local.views_selected.assign(n_cameras, 0);
  local.frames_in = frames.size();
  std::vector<WandFrame> selected;
  for (const FrameSet& set : frames) {
    WandFrame out;
    out.frame_number = set.frame_number;
    for (const CameraFrame& frame : set.cameras) {
      const auto it = index_of.find(frame.camera_id);
      if (it == index_of.end()) continue;
      const size_t camera = it->second;
      std::vector<Eigen::Vector2d> pixels;
      bool merged = false;
      for (const Blob& blob : frame.blobs) {
        if (masks[camera].IsStatic(blob.pixel)) {
          ++local.static_blobs_masked[camera];
          continue;
        }
        if ((blob.flags & kBlobMerged) != 0) merged = true;
        pixels.push_back(blob.pixel);
      }
      if (merged || pixels.size() != wand.MarkerCount()) continue;
      if (!OrderAlongWand(&pixels, options)) continue;
      WandView view;
      view.camera = camera;
      for (const Eigen::Vector2d& pixel : pixels) {
        view.normalized.push_back(rig.cameras[camera].UndistortPixel(pixel));
      }
      view.pixels = std::move(pixels);
      out.views.push_back(std::move(view));
    }
    if (static_cast<int>(out.views.size()) < options.min_views_per_frame) continue;
    for (const WandView& view : out.views) ++local.views_selected[view.camera];
    selected.push_back(std::move(out));
  }
  local.frames_selected = selected.size();
  if (stats != nullptr) *stats = std::move(local);
  return selected;
}

}  // namespace mocap

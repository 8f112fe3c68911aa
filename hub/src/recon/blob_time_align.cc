#include "recon/blob_time_align.h"

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace mocap {

void BlobTimeAlignOptions::Check() const {
  if (!(rate_hz > 0.0 && rate_hz <= 1e5))
    throw std::invalid_argument("time alignment: rate_hz must be in (0, 100000], not " + std::to_string(rate_hz));
  if (!(max_step_px > 0.0 && max_step_px <= 10000.0))
    throw std::invalid_argument("time alignment: max_step_px must be in (0, 10000], not " + std::to_string(max_step_px));
  if (!(offset_weight > 0.0 && offset_weight <= 1.0))
    throw std::invalid_argument("time alignment: offset_weight must be in (0, 1], not " +
                                std::to_string(offset_weight));
  if (!(predicted_gate_px > 0.0 && predicted_gate_px <= max_step_px))
    throw std::invalid_argument("time alignment: predicted_gate_px must be in (0, max_step_px], not " +
                                std::to_string(predicted_gate_px));
  if (max_gap_frames < 1 || max_gap_frames > 1000)
    throw std::invalid_argument("time alignment: max_gap_frames must be 1..1000, not " +
                                std::to_string(max_gap_frames));
}

BlobTimeAligner::BlobTimeAligner(const BlobTimeAlignOptions& options) : options_(options) {
  options_.Check();
  period_s_ = 1.0 / options_.rate_hz;
}

double BlobTimeAligner::OffsetS(uint32_t camera_id) const {
  const auto it = cameras_.find(camera_id);
  return it == cameras_.end() ? 0.0 : it->second.offset_s;
}

void BlobTimeAligner::Align(FrameSet* set) {
  for (CameraFrame& frame : set->cameras) AlignCamera(set->frame_number, &frame);
}

namespace {

// Index of the point in `points` nearest to p within its limit (limits[i], or `limit` for all when
// limits is empty), or -1.
int Nearest(const std::vector<Eigen::Vector2d>& points, const Eigen::Vector2d& p, double limit,
            const std::vector<double>& limits = {}) {
  int best = -1;
  double best_d2 = std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < points.size(); ++i) {
    const double d2 = (points[i] - p).squaredNorm();
    const double l = limits.empty() ? limit : limits[i];
    if (d2 < l * l && d2 < best_d2) {
      best_d2 = d2;
      best = static_cast<int>(i);
    }
  }
  return best;
}

}  // namespace

void BlobTimeAligner::AlignCamera(uint64_t set_number, CameraFrame* frame) {
  // Differences in integers first: nanoseconds since 1970 do not fit a double's mantissa.
  const double stamp_s =
      static_cast<double>(static_cast<int64_t>(frame->capture_time_ns - options_.epoch_ns)) * 1e-9;
  const double measured = stamp_s - static_cast<double>(set_number) / options_.rate_hz;
  auto [it, first] = cameras_.try_emplace(frame->camera_id);
  CameraTrack& track = it->second;
  const bool continues = !first && set_number > track.frame_number &&
                         set_number - track.frame_number <= static_cast<uint64_t>(options_.max_gap_frames);
  // The phase moves by the rate error only; a jump of a quarter period is a new phase.
  if (first || std::abs(measured - track.offset_s) > 0.25 * period_s_)
    track.offset_s = measured;
  else
    track.offset_s += options_.offset_weight * (measured - track.offset_s);

  std::vector<Eigen::Vector2d> pixels(frame->blobs.size());
  for (size_t b = 0; b < frame->blobs.size(); ++b) pixels[b] = frame->blobs[b].pixel;
  const Eigen::Vector2d unknown = Eigen::Vector2d::Constant(std::numeric_limits<double>::quiet_NaN());
  std::vector<Eigen::Vector2d> steps(pixels.size(), unknown);
  if (continues) {
    const double frames = static_cast<double>(set_number - track.frame_number);
    // The previous blobs carried on by their velocities, and how far from there a blob may be.
    std::vector<Eigen::Vector2d> predicted(track.pixels.size());
    std::vector<double> limits(track.pixels.size());
    for (size_t p = 0; p < track.pixels.size(); ++p) {
      const bool known = !std::isnan(track.steps[p].x());
      predicted[p] = known ? Eigen::Vector2d(track.pixels[p] + frames * track.steps[p]) : track.pixels[p];
      limits[p] = known ? options_.predicted_gate_px : options_.max_step_px * frames;
    }
    // Pixels per second times the time from the capture to the set's instant.
    const double scale = -track.offset_s / (frames * period_s_);
    for (size_t b = 0; b < pixels.size(); ++b) {
      const int p = Nearest(predicted, pixels[b], 0.0, limits);
      if (p < 0 || Nearest(pixels, predicted[static_cast<size_t>(p)], limits[static_cast<size_t>(p)]) !=
                       static_cast<int>(b)) {
        ++stats_.blobs_kept;
        continue;
      }
      const Eigen::Vector2d moved = pixels[b] - track.pixels[static_cast<size_t>(p)];
      steps[b] = moved / frames;
      // A pairing within a whole step may be a neighbour's blob: it starts the track, and the
      // blob moves once the track's prediction has found it again.
      if (std::isnan(track.steps[static_cast<size_t>(p)].x())) {
        ++stats_.blobs_kept;
        continue;
      }
      frame->blobs[b].pixel = pixels[b] + scale * moved;
      ++stats_.blobs_moved;
    }
  } else {
    stats_.blobs_kept += pixels.size();
  }
  track.frame_number = set_number;
  track.pixels = std::move(pixels);
  track.steps = std::move(steps);
}

}  // namespace mocap

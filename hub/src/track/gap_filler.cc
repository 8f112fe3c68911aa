// Windowed output with spline filling of short gaps.
#include "track/gap_filler.h"

namespace mocap {

GapFiller::GapFiller(const GapFillOptions& options, Sink sink)
    : options_((options.Check(), options)), sink_(std::move(sink)) {}

GapFiller::Row* GapFiller::RowOf(uint64_t frame_number) {
  if (rows_.empty() || frame_number < rows_.front().frame_number ||
      frame_number > rows_.back().frame_number) {
    return nullptr;
  }
  return &rows_[frame_number - rows_.front().frame_number];
}

void GapFiller::Put(const TrackSample& sample) {
  Row* row = RowOf(sample.frame_number);
  if (row == nullptr) {
    ++dropped_;
    return;
  }
  for (TrackSample& existing : row->samples) {
    if (existing.marker == sample.marker) {
      existing = sample;
      return;
    }
  }
  row->samples.push_back(sample);
}

void GapFiller::FillSpline(const LastMeasured& from, const TrackSample& to) {
  const double span = static_cast<double>(to.frame_number - from.frame_number);
  for (uint64_t frame = from.frame_number + 1; frame < to.frame_number; ++frame) {
    const double t = static_cast<double>(frame - from.frame_number) / span;
    const double t2 = t * t, t3 = t2 * t;
    // Cubic Hermite basis; velocities are per frame, so scale them by the span.
    const double h00 = 2 * t3 - 3 * t2 + 1, h10 = t3 - 2 * t2 + t;
    const double h01 = -2 * t3 + 3 * t2, h11 = t3 - t2;
    TrackSample sample;
    sample.marker = to.marker;
    sample.frame_number = frame;
    sample.position = h00 * from.position + h10 * span * from.velocity_per_frame +
                      h01 * to.position + h11 * span * to.velocity_per_frame;
    sample.kind = SampleKind::kFilled;
    Put(sample);
    ++filled_;
  }
}

void GapFiller::Add(uint64_t frame_number, const std::vector<TrackSample>& samples) {
  if (rows_.empty()) {
    // Start at the earliest frame the samples mention (a confirmation back-fills a few).
    uint64_t first = frame_number;
    for (const TrackSample& s : samples) first = std::min(first, s.frame_number);
    rows_.push_back({first, {}});
  }
  // A pause longer than the window cannot be spline-filled: the held rows go out and the window
  // restarts at this frame, so the cost follows the frames processed, not the frame-number span.
  // Such a pause has no TRC rows (the rows carry their frame number and time).
  if (frame_number > rows_.back().frame_number &&
      frame_number - rows_.back().frame_number > static_cast<uint64_t>(options_.window_frames)) {
    Finish();
    rows_.push_back({frame_number, {}});
  }
  while (rows_.back().frame_number < frame_number) rows_.push_back({rows_.back().frame_number + 1, {}});

  for (const TrackSample& sample : samples) {
    if (sample.marker >= static_cast<int>(last_.size())) last_.resize(sample.marker + 1);
    Put(sample);
    if (sample.kind != SampleKind::kMeasured) continue;
    LastMeasured& last = last_[sample.marker];
    if (last.valid && sample.frame_number > last.frame_number + 1 &&
        sample.frame_number - last.frame_number - 1 <= static_cast<uint64_t>(options_.max_spline_gap) &&
        last.frame_number >= rows_.front().frame_number) {
      FillSpline(last, sample);
    }
    if (!last.valid || sample.frame_number > last.frame_number) {
      last.valid = true;
      last.frame_number = sample.frame_number;
      last.position = sample.position;
      last.velocity_per_frame = sample.velocity_per_frame;
    }
  }
  while (rows_.size() > static_cast<size_t>(options_.window_frames)) {
    sink_(rows_.front().frame_number, rows_.front().samples);
    rows_.pop_front();
  }
}

void GapFiller::Finish() {
  while (!rows_.empty()) {
    sink_(rows_.front().frame_number, rows_.front().samples);
    rows_.pop_front();
  }
}

}  // namespace mocap

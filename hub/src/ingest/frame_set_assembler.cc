// Live frame-set assembly with deadlines (see frame_set_assembler.h).
#include "ingest/frame_set_assembler.h"

#include <cmath>
#include <stdexcept>

namespace mocap {

void FrameSetAssemblerOptions::Check() const {
  if (deadline_ns == 0) throw std::invalid_argument("assembly deadline must be positive");
  if (free_run && !(rate_hz > 0.0)) throw std::invalid_argument("free-run grouping needs the frame rate");
  if (max_open_sets == 0) throw std::invalid_argument("max_open_sets must be positive");
  if (!(rate_hz >= 0.0) || !std::isfinite(rate_hz)) throw std::invalid_argument("frame rate must be a finite number >= 0");
}

FrameSetAssembler::FrameSetAssembler(FrameSetAssemblerOptions options, std::vector<uint32_t> expected)
    : options_(options), expected_(expected.begin(), expected.end()) {
  options_.Check();
  if (options_.free_run && options_.free_run_tolerance_ns == 0)
    options_.free_run_tolerance_ns = static_cast<uint64_t>(1e9 / options_.rate_hz / 3.0);
  clock_known_ = !options_.free_run && options_.rate_hz > 0.0 && options_.epoch_ns > 0 && options_.clock_window_ns > 0;
}

double FrameSetAssembler::ClockOffsetS(uint64_t frame_number, uint64_t now_ns) const {
  if (!clock_known_) return 0.0;
  // Doubles hold any frame number's time to far better than the window for sessions of years.
  const double since_epoch_s = now_ns >= options_.epoch_ns ? double(now_ns - options_.epoch_ns) * 1e-9
                                                            : -double(options_.epoch_ns - now_ns) * 1e-9;
  return double(frame_number) / options_.rate_hz - since_epoch_s;
}

bool FrameSetAssembler::OnSessionClock(uint64_t frame_number, uint64_t now_ns) const {
  if (!clock_known_) return true;
  const double ahead_s = ClockOffsetS(frame_number, now_ns);
  const double window_s = double(options_.clock_window_ns) * 1e-9;
  return ahead_s <= window_s && -ahead_s <= window_s + double(options_.deadline_ns) * 1e-9;
}

uint64_t FrameSetAssembler::KeyFor(const CameraFrame& frame) const {
  if (!options_.free_run) return frame.frame_number;
  const uint64_t t = frame.capture_time_ns;
  for (const auto& [key, open] : open_) {
    const uint64_t d = t > open.reference_time_ns ? t - open.reference_time_ns : open.reference_time_ns - t;
    if (d <= options_.free_run_tolerance_ns) return key;
  }
  const double since_epoch = t > options_.epoch_ns ? double(t - options_.epoch_ns) : 0.0;
  return static_cast<uint64_t>(std::llround(since_epoch * 1e-9 * options_.rate_hz));
}

bool FrameSetAssembler::Add(CameraFrame frame, uint64_t now_ns) {
  if (!OnSessionClock(frame.frame_number, now_ns)) {
    ++off_clock_;
    return false;
  }
  const uint64_t key = KeyFor(frame);
  if (emitted_any_ && key <= last_emitted_) {
    ++late_;
    return false;
  }
  auto it = open_.find(key);
  if (it == open_.end()) {
    Open open;
    open.set.frame_number = key;
    open.first_arrival_ns = now_ns;
    open.reference_time_ns = frame.capture_time_ns;
    it = open_.emplace(key, std::move(open)).first;
  }
  for (const CameraFrame& existing : it->second.set.cameras)
    if (existing.camera_id == frame.camera_id) {
      ++duplicates_;
      return false;
    }
  frame.frame_number = key;
  it->second.set.cameras.push_back(std::move(frame));
  return true;
}

std::vector<FrameSet> FrameSetAssembler::Collect(uint64_t now_ns) {
  std::vector<FrameSet> out;
  // Sets leave in frame-number order: a complete set waits behind an older open one only until
  // that one's deadline, which keeps the output ordered without blocking for long.
  while (!open_.empty()) {
    auto it = open_.begin();
    const bool complete = !expected_.empty() && it->second.set.cameras.size() >= expected_.size();
    const bool expired = now_ns >= it->second.first_arrival_ns + options_.deadline_ns;
    const bool overflow = open_.size() > options_.max_open_sets;
    if (!complete && !expired && !overflow) break;
    if (!complete) CountIncomplete(it->second.set);
    emitted_any_ = true;
    last_emitted_ = it->first;
    out.push_back(std::move(it->second.set));
    open_.erase(it);
  }
  return out;
}

void FrameSetAssembler::CountIncomplete(const FrameSet& set) {
  ++incomplete_;
  if (set.cameras.size() == 1 && expected_.size() >= 2) ++single_camera_;
}

std::vector<FrameSet> FrameSetAssembler::Flush() {
  std::vector<FrameSet> out;
  for (auto& [key, open] : open_) {
    if (expected_.empty() || open.set.cameras.size() < expected_.size()) CountIncomplete(open.set);
    emitted_any_ = true;
    last_emitted_ = key;
    out.push_back(std::move(open.set));
  }
  open_.clear();
  return out;
}

}  // namespace mocap

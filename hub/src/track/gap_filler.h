// Gap filling after the fact within a bounded window: output rows are held back window_frames
// frames; when a marker is measured again after a gap of at most max_spline_gap frames, the gap
// (empty, or rigid-model predictions) is replaced by a cubic Hermite spline through the measured
// ends and their velocities. Longer gaps keep the rigid-model (linked markers) positions the
// tracker produced. Memory is bounded by the window, whatever the session length.
#pragma once

#include <cstdint>
#include <deque>
#include <functional>
#include <vector>

#include "track/track_options.h"
#include "track/tracker.h"

namespace mocap {

class GapFiller {
 public:
  // Receives frame numbers in order with their samples (possibly none): every frame number,
  // except those inside a pause longer than window_frames.
  using Sink = std::function<void(uint64_t frame_number, const std::vector<TrackSample>& row)>;

  // Checks the options (std::invalid_argument).
  GapFiller(const GapFillOptions& options, Sink sink);

  // Adds the tracker's samples after frame `frame_number` was processed. Samples older than
  // the window are dropped (counted in dropped_samples()).
  void Add(uint64_t frame_number, const std::vector<TrackSample>& samples);
  // Emits every row still held.
  void Finish();

  long long filled_samples() const { return filled_; }
  long long dropped_samples() const { return dropped_; }

 private:
  struct Row {
    uint64_t frame_number = 0;
    std::vector<TrackSample> samples;
  };
  struct LastMeasured {
    bool valid = false;
    uint64_t frame_number = 0;
    Eigen::Vector3d position = Eigen::Vector3d::Zero();
    Eigen::Vector3d velocity_per_frame = Eigen::Vector3d::Zero();
  };

  Row* RowOf(uint64_t frame_number);
  void Put(const TrackSample& sample);
  void FillSpline(const LastMeasured& from, const TrackSample& to);

  GapFillOptions options_;
  Sink sink_;
  std::deque<Row> rows_;
  std::vector<LastMeasured> last_;  // by marker
  long long filled_ = 0;
  long long dropped_ = 0;
};

}  // namespace mocap

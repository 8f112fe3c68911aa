// Live assembly of camera frames into frame sets. A set is handed out as soon as every expected
// camera has delivered, or when its deadline passes (late and missing cameras never block the
// stream); frames that arrive after their set left are counted as late and dropped.
// Triggered mode keys sets by the nodes' global frame number. With the session clock known
// (epoch and rate), a frame whose trigger time (epoch + number / rate) lies further than a window
// from its arrival is off the session clock -- forged, or from a node whose clock or epoch is
// wrong -- and is refused before it opens a set, so one bad frame number never moves the window
// the other nodes' frames are assembled in. Free-run mode (no trigger wire) groups frames whose
// capture times lie within a tolerance and numbers the set by its time.
#pragma once

#include <cstdint>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "ingest/camera_frame.h"

namespace mocap {

struct FrameSetAssemblerOptions {
  uint64_t deadline_ns = 20'000'000;       // how long a set waits for missing cameras
  bool free_run = false;
  double rate_hz = 0.0;                   // free run: frame numbering, tolerance default
  uint64_t epoch_ns = 0;                  // free run: time of frame 0
  uint64_t free_run_tolerance_ns = 0;     // 0 = a third of the frame period
  size_t max_open_sets = 256;             // beyond this the oldest set is handed out early
  // Triggered mode with epoch_ns and rate_hz set: how far a frame's trigger time may lie ahead of
  // its arrival, or behind it beyond the deadline (clock error + network + node latency); 0 = off.
  uint64_t clock_window_ns = 250'000'000;

  // Throws std::invalid_argument naming the first unusable setting (the hub's options policy).
  void Check() const;
};

class FrameSetAssembler {
 public:
  FrameSetAssembler(FrameSetAssemblerOptions options, std::vector<uint32_t> expected_cameras);

  // Whether frame `number`, arriving at now_ns, fits the session clock (always true in free run
  // or without epoch and rate).
  bool OnSessionClock(uint64_t frame_number, uint64_t now_ns) const;
  // Seconds frame `number`'s trigger time lies ahead of now_ns on the session clock (negative:
  // behind); 0 when the clock is not known.
  double ClockOffsetS(uint64_t frame_number, uint64_t now_ns) const;
  // Adds a camera frame received at now_ns. Returns false when it was dropped as off the session
  // clock, as late, or as a duplicate of a camera already in its set.
  bool Add(CameraFrame frame, uint64_t now_ns);
  // Sets that are complete or past their deadline at now_ns, in frame-number order.
  std::vector<FrameSet> Collect(uint64_t now_ns);
  // Everything still open (end of recording).
  std::vector<FrameSet> Flush();

  uint64_t late_frames() const { return late_; }
  uint64_t duplicate_frames() const { return duplicates_; }
  uint64_t incomplete_sets() const { return incomplete_; }
  // Sets handed out with one camera while two or more are expected: nothing in them can be
  // triangulated (under load, the other cameras' frames came after the deadline).
  uint64_t single_camera_sets() const { return single_camera_; }
  uint64_t off_clock_frames() const { return off_clock_; }

 private:
  struct Open {
    FrameSet set;
    uint64_t first_arrival_ns = 0;
    uint64_t reference_time_ns = 0;  // free run: capture time of the first frame
  };
  uint64_t KeyFor(const CameraFrame& frame) const;

  FrameSetAssemblerOptions options_;
  std::set<uint32_t> expected_;
  std::map<uint64_t, Open> open_;
  bool emitted_any_ = false;
  uint64_t last_emitted_ = 0;
  bool clock_known_ = false;
  void CountIncomplete(const FrameSet& set);

  uint64_t late_ = 0, duplicates_ = 0, incomplete_ = 0, single_camera_ = 0, off_clock_ = 0;
};

}  // namespace mocap

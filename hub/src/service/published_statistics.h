// What the live hub published, for /api/status: counts of frame sets and points, and three
// latency reservoirs (the hub's own, the processing of a set, the nodes' trigger -> send). The
// loop adds every published frame; the percentiles, which sort a copy of a reservoir of up to
// 100 000 samples, are recomputed by the loop at most once per `refresh_ns` (Refresh, from its
// tick) and only when samples came since, never per status request. Counts, maxima and sample
// counts are exact at every Add.
//
// Threads: Add and Refresh on the loop only; Summary and AddTo on any thread (they read the
// latest snapshot under a mutex, a few numbers, nothing proportional to a reservoir).
#pragma once

#include <cstdint>
#include <mutex>

#include <nlohmann/json.hpp>

#include "ingest/camera_frame.h"
#include "pipeline/live_frame.h"
#include "util/latency_sample.h"

namespace mocap::service {

struct LatencySummary {
  double p50 = 0.0;     // of the reservoir at the last refresh; 0 before any
  double p99 = 0.0;
  double max = 0.0;     // exact
  uint64_t count = 0;   // exact
};

struct PublishedSummary {
  uint64_t frame_sets = 0;
  uint64_t points = 0;
  uint64_t provisional_points = 0;
  LatencySummary hub_ms;         // complete frame sets: last datagram received -> result published
  LatencySummary processing_ms;  // reconstruction + tracking of one frame set
  LatencySummary node_ms;        // per camera frame: trigger -> the node sent it, node clocks
};

class PublishedStatistics {
 public:
  static constexpr uint64_t kDefaultRefreshNs = 1'000'000'000;

  // Throws std::invalid_argument when refresh_ns is 0 or capacity is 0.
  explicit PublishedStatistics(uint64_t refresh_ns = kDefaultRefreshNs, size_t capacity = 100000);

  // Loop: one published frame of `set`, whose processing started at processing_start_ns; the
  // hub's latency counts only sets with all `rig_cameras` (a set that waited out its deadline
  // for an absent camera measures the deadline, not the hub).
  void Add(const FrameSet& set, const pipeline::LiveFrame& frame, size_t rig_cameras, uint64_t processing_start_ns);
  // Loop: recomputes the percentiles when refresh_ns passed since the last refresh and samples
  // came since.
  void Refresh(uint64_t now_ns);

  // Any thread.
  PublishedSummary Summary() const;
  // Any thread: the summary's fields of /api/status (frame_sets, points_published,
  // provisional_points_published, hub_latency_ms, processing_ms, node_latency_ms) into status.
  void AddTo(nlohmann::json* status) const;

 private:
  const uint64_t refresh_ns_;
  // Loop-owned.
  LatencySample hub_ms_, processing_ms_, node_ms_;
  bool fresh_samples_ = false;   // samples added since the last refresh
  uint64_t next_refresh_ns_ = 0;

  mutable std::mutex mutex_;
  PublishedSummary summary_;     // under mutex_
};

}  // namespace mocap::service

// What the live hub published, snapshotted for /api/status (see published_statistics.h).
#include "service/published_statistics.h"

#include <stdexcept>

namespace mocap::service {
namespace {

double Ms(uint64_t from_ns, uint64_t to_ns) { return static_cast<double>(to_ns - from_ns) * 1e-6; }

// Count and maximum (exact); the percentiles stay those of the last refresh.
void Count(const LatencySample& sample, LatencySummary* summary) {
  summary->max = sample.max();
  summary->count = sample.count();
}

void Percentiles(const LatencySample& sample, LatencySummary* summary) {
  summary->p50 = sample.Percentile(50);
  summary->p99 = sample.Percentile(99);
}

}  // namespace

PublishedStatistics::PublishedStatistics(uint64_t refresh_ns, size_t capacity)
    : refresh_ns_(refresh_ns), hub_ms_(capacity), processing_ms_(capacity), node_ms_(capacity) {
  if (refresh_ns == 0) throw std::invalid_argument("statistics refresh period must be > 0 ns");
  if (capacity == 0) throw std::invalid_argument("statistics reservoir capacity must be > 0");
}

void PublishedStatistics::Add(const FrameSet& set, const pipeline::LiveFrame& frame, size_t rig_cameras,
                              uint64_t processing_start_ns) {
  processing_ms_.Add(Ms(processing_start_ns, frame.publish_ns));
  if (set.cameras.size() == rig_cameras && frame.last_receive_ns && frame.publish_ns >= frame.last_receive_ns)
    hub_ms_.Add(Ms(frame.last_receive_ns, frame.publish_ns));
  for (const CameraFrame& camera : set.cameras)
    if (camera.trigger_time_ns && camera.send_time_ns >= camera.trigger_time_ns)
      node_ms_.Add(Ms(camera.trigger_time_ns, camera.send_time_ns));
  fresh_samples_ = true;
  uint64_t provisional = 0;
  for (const pipeline::LivePoint& p : frame.points) provisional += p.provisional();
  std::lock_guard<std::mutex> lock(mutex_);
  ++summary_.frame_sets;
  summary_.points += frame.points.size();
  summary_.provisional_points += provisional;
  Count(hub_ms_, &summary_.hub_ms);
  Count(processing_ms_, &summary_.processing_ms);
  Count(node_ms_, &summary_.node_ms);
}

void PublishedStatistics::Refresh(uint64_t now_ns) {
  if (!fresh_samples_ || now_ns < next_refresh_ns_) return;
  fresh_samples_ = false;
  next_refresh_ns_ = now_ns + refresh_ns_;
  // Sorted outside the lock: a reader waits for a few numbers, not for the sort.
  LatencySummary hub, processing, node;
  Percentiles(hub_ms_, &hub);
  Percentiles(processing_ms_, &processing);
  Percentiles(node_ms_, &node);
  std::lock_guard<std::mutex> lock(mutex_);
  summary_.hub_ms.p50 = hub.p50;
  summary_.hub_ms.p99 = hub.p99;
  summary_.processing_ms.p50 = processing.p50;
  summary_.processing_ms.p99 = processing.p99;
  summary_.node_ms.p50 = node.p50;
  summary_.node_ms.p99 = node.p99;
}

PublishedSummary PublishedStatistics::Summary() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return summary_;
}

void PublishedStatistics::AddTo(nlohmann::json* status) const {
  const PublishedSummary s = Summary();
  nlohmann::json& j = *status;
  j["frame_sets"] = s.frame_sets;
  j["points_published"] = s.points;
  j["provisional_points_published"] = s.provisional_points;
  j["hub_latency_ms"] = {{"p50", s.hub_ms.p50},
                         {"p99", s.hub_ms.p99},
                         {"max", s.hub_ms.max},
                         {"frame_sets", s.hub_ms.count},
                         {"definition", "complete frame sets: last datagram received (kernel time) -> 3D result published"}};
  j["processing_ms"] = {{"p50", s.processing_ms.p50},
                        {"p99", s.processing_ms.p99},
                        {"max", s.processing_ms.max},
                        {"definition", "reconstruction + tracking of one frame set"}};
  j["node_latency_ms"] = {{"p50", s.node_ms.p50},
                          {"p99", s.node_ms.p99},
                          {"max", s.node_ms.max},
                          {"definition", "trigger (mid-exposure) -> the node sent the frame's datagrams, node clocks"}};
}

}  // namespace mocap::service

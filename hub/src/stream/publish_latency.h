// Every adapter's latency figures, as /api/status and the benchmarks report them, per frame sent:
//   publish_to_sent_ms  the 3D result's publication -> the adapter's last datagram or report handed
//                       to the kernel: what its reader waits for on the hub, including the adapters
//                       that sent the same frame before it on the loop;
//   adds_ms             what the adapter itself adds: from the moment it took the frame up (its
//                       encoding included) to the same hand-off.
// Threads: Add from the adapter's sending thread, Json from any; the caller holds its stats lock.
#pragma once

#include <cstdint>
#include <string>

#include <nlohmann/json_fwd.hpp>

#include "util/latency_sample.h"

namespace mocap::stream {

class PublishLatency {
 public:
  // Clock readings in ns on the hub's clock; a reading out of order (a clock step) is not counted.
  void Add(uint64_t publish_ns, uint64_t began_ns, uint64_t sent_ns);
  // {"publish_to_sent_ms": {...}, "adds_ms": {...}}, each {"p50", "p99", "max", "frames",
  // "definition"} in milliseconds; `what` names the adapter's unit ("NatNet datagram").
  nlohmann::json Json(const std::string& what) const;
  const LatencySample& publish_to_sent_ms() const { return publish_to_sent_ms_; }

 private:
  LatencySample publish_to_sent_ms_{20000};
  LatencySample adds_ms_{20000};
};

}  // namespace mocap::stream

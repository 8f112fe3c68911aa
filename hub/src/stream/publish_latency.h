// Every adapter's own cost, as /api/status and the benchmarks report it: from the 3D result's
// publication to its last datagram or report handed to the kernel.
#pragma once

#include <string>

#include <nlohmann/json_fwd.hpp>

#include "util/latency_sample.h"

namespace mocap::stream {

// {"p50", "p99", "max", "frames", "definition"}; milliseconds.
nlohmann::json PublishToSentJson(const LatencySample& publish_to_sent_ms, const std::string& definition);

}  // namespace mocap::stream

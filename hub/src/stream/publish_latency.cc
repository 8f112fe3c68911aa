#include "stream/publish_latency.h"

#include <nlohmann/json.hpp>

namespace mocap::stream {

nlohmann::json PublishToSentJson(const LatencySample& publish_to_sent_ms, const std::string& definition) {
  return {{"p50", publish_to_sent_ms.Percentile(50)},
          {"p99", publish_to_sent_ms.Percentile(99)},
          {"max", publish_to_sent_ms.max()},
          {"frames", publish_to_sent_ms.count()},
          {"definition", definition}};
}

}  // namespace mocap::stream

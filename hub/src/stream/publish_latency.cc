#include "stream/publish_latency.h"

#include <nlohmann/json.hpp>

namespace mocap::stream {
namespace {

nlohmann::json Figures(const LatencySample& sample, const std::string& definition) {
  return {{"p50", sample.Percentile(50)},
          {"p99", sample.Percentile(99)},
          {"max", sample.max()},
          {"frames", sample.count()},
          {"definition", definition}};
}

}  // namespace

void PublishLatency::Add(uint64_t publish_ns, uint64_t began_ns, uint64_t sent_ns) {
  if (sent_ns >= publish_ns) publish_to_sent_ms_.Add(static_cast<double>(sent_ns - publish_ns) * 1e-6);
  if (sent_ns >= began_ns) adds_ms_.Add(static_cast<double>(sent_ns - began_ns) * 1e-6);
}

nlohmann::json PublishLatency::Json(const std::string& what) const {
  return {{"publish_to_sent_ms", Figures(publish_to_sent_ms_, "3D result published -> its last " + what +
                                                                  " handed to the kernel")},
          {"adds_ms", Figures(adds_ms_, "this adapter's own time: the frame taken up (encoded) -> its last " +
                                            what + " handed to the kernel")}};
}

}  // namespace mocap::stream

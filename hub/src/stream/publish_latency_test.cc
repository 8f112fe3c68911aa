#include "stream/publish_latency.h"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

namespace mocap::stream {
namespace {

constexpr uint64_t kMs = 1'000'000;

TEST(PublishLatency, SeparatesTheWaitForEarlierAdaptersFromItsOwnPart) {
  PublishLatency latency;
  // Published at 100 ms; the adapter took the frame up 2 ms later and sent it 0.5 ms after that.
  for (int i = 0; i < 10; ++i) latency.Add(100 * kMs, 102 * kMs, 102 * kMs + kMs / 2);
  const nlohmann::json j = latency.Json("datagram");
  EXPECT_NEAR(j["publish_to_sent_ms"]["p50"].get<double>(), 2.5, 1e-9);
  EXPECT_NEAR(j["adds_ms"]["p50"].get<double>(), 0.5, 1e-9);
  EXPECT_EQ(j["adds_ms"]["frames"].get<uint64_t>(), 10u);
  EXPECT_NE(j["publish_to_sent_ms"]["definition"].get<std::string>().find("datagram"), std::string::npos);
}

TEST(PublishLatency, AClockReadingOutOfOrderIsNotCounted) {
  PublishLatency latency;
  latency.Add(200 * kMs, 100 * kMs, 150 * kMs);  // sent "before" publication: the clock stepped back
  const nlohmann::json j = latency.Json("datagram");
  EXPECT_EQ(j["publish_to_sent_ms"]["frames"].get<uint64_t>(), 0u);
  EXPECT_EQ(j["adds_ms"]["frames"].get<uint64_t>(), 1u);
}

}  // namespace
}  // namespace mocap::stream

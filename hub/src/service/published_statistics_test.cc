// What the hub published, without a loop or a socket: counts exact at every frame, the
// percentiles from the last refresh only, refreshed when due and when samples came, and the
// /api/status fields they fill.
#include "service/published_statistics.h"

#include <stdexcept>

#include <gtest/gtest.h>

namespace mocap::service {
namespace {

constexpr uint64_t kMs = 1'000'000;
constexpr uint64_t kRefresh = 100 * kMs;

// A set of `cameras` camera frames, each sent node_ms after its trigger.
FrameSet Set(size_t cameras, uint64_t node_ms) {
  FrameSet set;
  for (size_t c = 0; c < cameras; ++c) {
    CameraFrame frame;
    frame.camera_id = static_cast<uint32_t>(c + 1);
    frame.trigger_time_ns = 1000 * kMs;
    frame.send_time_ns = frame.trigger_time_ns + node_ms * kMs;
    set.cameras.push_back(frame);
  }
  return set;
}

// A frame received at 0, published hub_ms later, with `points` points of which `provisional`
// are not confirmed.
pipeline::LiveFrame Frame(uint64_t hub_ms, int points, int provisional) {
  pipeline::LiveFrame frame;
  frame.last_receive_ns = 5000 * kMs;
  frame.publish_ns = frame.last_receive_ns + hub_ms * kMs;
  for (int p = 0; p < points; ++p) {
    pipeline::LivePoint point;
    point.marker = p < provisional ? -1 : p;
    frame.points.push_back(point);
  }
  return frame;
}

TEST(PublishedStatistics, RefusesAZeroPeriodOrCapacity) {
  EXPECT_THROW(PublishedStatistics(0), std::invalid_argument);
  EXPECT_THROW(PublishedStatistics(kRefresh, 0), std::invalid_argument);
}

TEST(PublishedStatistics, CountsAreExactAtEveryFrame) {
  PublishedStatistics stats(kRefresh);
  const pipeline::LiveFrame frame = Frame(3, 4, 1);
  stats.Add(Set(3, 2), frame, 3, frame.publish_ns - 1 * kMs);
  stats.Add(Set(3, 2), frame, 3, frame.publish_ns - 1 * kMs);
  const PublishedSummary s = stats.Summary();
  EXPECT_EQ(s.frame_sets, 2u);
  EXPECT_EQ(s.points, 8u);
  EXPECT_EQ(s.provisional_points, 2u);
  EXPECT_EQ(s.hub_ms.count, 2u);
  EXPECT_DOUBLE_EQ(s.hub_ms.max, 3.0);
  EXPECT_EQ(s.processing_ms.count, 2u);
  EXPECT_DOUBLE_EQ(s.processing_ms.max, 1.0);
  EXPECT_EQ(s.node_ms.count, 6u);  // one per camera frame
  EXPECT_DOUBLE_EQ(s.node_ms.max, 2.0);
}

TEST(PublishedStatistics, HubLatencyOnlyOfCompleteSets) {
  PublishedStatistics stats(kRefresh);
  const pipeline::LiveFrame frame = Frame(20, 0, 0);
  stats.Add(Set(2, 1), frame, 3, frame.publish_ns);  // a camera missing: waited out the deadline
  const PublishedSummary s = stats.Summary();
  EXPECT_EQ(s.frame_sets, 1u);
  EXPECT_EQ(s.hub_ms.count, 0u);
  EXPECT_EQ(s.node_ms.count, 2u);
}

TEST(PublishedStatistics, PercentilesChangeOnlyWhenRefreshed) {
  PublishedStatistics stats(kRefresh);
  const pipeline::LiveFrame fast = Frame(2, 0, 0);
  stats.Add(Set(2, 1), fast, 2, fast.publish_ns);
  EXPECT_EQ(stats.Summary().hub_ms.p50, 0.0);  // none computed yet
  stats.Refresh(1000 * kMs);
  EXPECT_DOUBLE_EQ(stats.Summary().hub_ms.p50, 2.0);
  EXPECT_DOUBLE_EQ(stats.Summary().node_ms.p99, 1.0);

  // New samples before the period is over: counts move, percentiles stay.
  const pipeline::LiveFrame slow = Frame(8, 0, 0);
  for (int n = 0; n < 3; ++n) stats.Add(Set(2, 1), slow, 2, slow.publish_ns);
  stats.Refresh(1000 * kMs + kRefresh - 1);
  EXPECT_EQ(stats.Summary().hub_ms.count, 4u);
  EXPECT_DOUBLE_EQ(stats.Summary().hub_ms.max, 8.0);
  EXPECT_DOUBLE_EQ(stats.Summary().hub_ms.p50, 2.0);

  // The period over: the percentiles of every sample.
  stats.Refresh(1000 * kMs + kRefresh);
  EXPECT_DOUBLE_EQ(stats.Summary().hub_ms.p50, 8.0);
  EXPECT_DOUBLE_EQ(stats.Summary().hub_ms.p99, 8.0);
}

TEST(PublishedStatistics, NothingNewNothingRecomputedAndTheNextSampleRefreshesAtOnce) {
  PublishedStatistics stats(kRefresh);
  const pipeline::LiveFrame a = Frame(2, 0, 0);
  stats.Add(Set(2, 1), a, 2, a.publish_ns);
  stats.Refresh(1000 * kMs);
  // Idle for longer than the period: the next sample is refreshed at the first tick after it.
  stats.Refresh(5000 * kMs);
  const pipeline::LiveFrame b = Frame(6, 0, 0);
  for (int n = 0; n < 3; ++n) stats.Add(Set(2, 1), b, 2, b.publish_ns);
  stats.Refresh(5000 * kMs + 1);
  EXPECT_DOUBLE_EQ(stats.Summary().hub_ms.p50, 6.0);
}

TEST(PublishedStatistics, FillsTheStatusFields) {
  PublishedStatistics stats(kRefresh);
  const pipeline::LiveFrame frame = Frame(4, 3, 2);
  stats.Add(Set(2, 1), frame, 2, frame.publish_ns - 2 * kMs);
  stats.Refresh(1000 * kMs);
  nlohmann::json status = {{"udp_port", 30000}};
  stats.AddTo(&status);
  EXPECT_EQ(status["udp_port"], 30000);  // other fields kept
  EXPECT_EQ(status["frame_sets"], 1);
  EXPECT_EQ(status["points_published"], 3);
  EXPECT_EQ(status["provisional_points_published"], 2);
  EXPECT_DOUBLE_EQ(status["hub_latency_ms"]["p50"].get<double>(), 4.0);
  EXPECT_DOUBLE_EQ(status["hub_latency_ms"]["p99"].get<double>(), 4.0);
  EXPECT_DOUBLE_EQ(status["hub_latency_ms"]["max"].get<double>(), 4.0);
  EXPECT_EQ(status["hub_latency_ms"]["frame_sets"], 1);
  EXPECT_TRUE(status["hub_latency_ms"]["definition"].is_string());
  EXPECT_DOUBLE_EQ(status["processing_ms"]["p50"].get<double>(), 2.0);
  EXPECT_DOUBLE_EQ(status["processing_ms"]["max"].get<double>(), 2.0);
  EXPECT_TRUE(status["processing_ms"]["definition"].is_string());
  EXPECT_DOUBLE_EQ(status["node_latency_ms"]["p99"].get<double>(), 1.0);
  EXPECT_DOUBLE_EQ(status["node_latency_ms"]["max"].get<double>(), 1.0);
  EXPECT_TRUE(status["node_latency_ms"]["definition"].is_string());
}

}  // namespace
}  // namespace mocap::service

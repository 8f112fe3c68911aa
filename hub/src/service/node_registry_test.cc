// The node table: status and frames attribute to nodes, lost and back by time alone, address
// changes and restarts reported, and unattributable datagrams counted in a bounded table.
#include "service/node_registry.h"

#include <gtest/gtest.h>

namespace mocap::service {
namespace {

constexpr uint64_t kSecond = 1'000'000'000;

v1::Packet Status(uint32_t node, uint64_t uptime_ms = 1000) {
  v1::Packet p;
  p.set_version(1);
  v1::NodeStatus* s = p.mutable_node_status();
  s->set_node_id(node);
  s->set_state(v1::NODE_STATE_RUNNING);
  s->set_firmware_version("0.1.0");
  s->set_uptime_ms(uptime_ms);
  s->set_fps_milli(239987);
  s->set_detect_time_us_mean(800);
  s->set_detect_time_us_max(2300);
  s->set_frames_captured(1000);
  s->set_frames_sent(990);
  s->set_frames_dropped(10);
  s->mutable_sync()->set_edge_jitter_ns(1800);
  s->mutable_sync()->set_missed_edges(2);
  s->set_has_temperature(true);
  s->set_temperature_mdeg(-5250);
  s->set_threshold(90);
  s->set_exposure_us(500);
  s->set_gain_milli(2500);
  return p;
}

v1::Packet Frame(uint32_t node, uint64_t frame_number) {
  v1::Packet p;
  p.set_version(1);
  p.mutable_marker_frame()->set_node_id(node);
  p.mutable_marker_frame()->set_frame_number(frame_number);
  return p;
}

TEST(NodeRegistry, StatusFillsTheEntry) {
  NodeRegistry registry;
  const auto events = registry.OnPacket(Status(3), "10.0.0.3:40000", 5 * kSecond);
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events[0].kind, RegistryEventKind::kJoined);
  const NodeEntry* e = registry.Find(3);
  ASSERT_NE(e, nullptr);
  EXPECT_EQ(e->address, "10.0.0.3:40000");
  EXPECT_EQ(e->state, NodeState::kRunning);
  EXPECT_STREQ(NodeStateName(e->state), "running");
  EXPECT_EQ(e->firmware_version, "0.1.0");
  EXPECT_DOUBLE_EQ(e->fps, 239.987);
  EXPECT_EQ(e->detect_time_us_mean, 800u);
  EXPECT_EQ(e->detect_time_us_max, 2300u);
  EXPECT_EQ(e->frames_dropped, 10u);
  EXPECT_TRUE(e->has_temperature);
  EXPECT_DOUBLE_EQ(e->temperature_c, -5.25);
  EXPECT_EQ(e->sync.edge_jitter_ns, 1800u);
  EXPECT_EQ(e->sync.missed_edges, 2u);
  EXPECT_EQ(e->threshold, 90u);
  EXPECT_EQ(e->exposure_us, 500u);
  EXPECT_EQ(e->gain_milli, 2500u);
  EXPECT_EQ(e->last_seen_ns, 5 * kSecond);
  EXPECT_FALSE(e->lost);
}

TEST(NodeRegistry, MarkerFramesKeepANodeAliveWithoutStatus) {
  NodeRegistry registry;
  registry.OnPacket(Frame(4, 100), "10.0.0.4:1", 0);
  registry.OnPacket(Frame(4, 102), "10.0.0.4:1", kSecond);
  registry.OnPacket(Frame(4, 101), "10.0.0.4:1", kSecond);  // a late chunk
  const NodeEntry* e = registry.Find(4);
  ASSERT_NE(e, nullptr);
  EXPECT_FALSE(e->has_status);
  EXPECT_EQ(e->state, NodeState::kUnknown);
  EXPECT_EQ(e->marker_datagrams, 3u);
  EXPECT_EQ(e->last_frame_number, 102u);
  EXPECT_TRUE(registry.Tick(3 * kSecond).empty());
}

TEST(NodeRegistry, SilentNodeIsLostAndComesBackByItself) {
  NodeRegistryOptions options;
  options.lost_after_ns = 3 * kSecond;
  NodeRegistry registry(options);
  registry.OnPacket(Status(1), "a:1", 0);
  registry.OnPacket(Status(2), "b:1", 0);
  registry.OnPacket(Status(2), "b:1", 2 * kSecond);
  EXPECT_TRUE(registry.Tick(3 * kSecond).empty());
  auto lost = registry.Tick(3 * kSecond + 1);
  ASSERT_EQ(lost.size(), 1u);
  EXPECT_EQ(lost[0].kind, RegistryEventKind::kLost);
  EXPECT_EQ(lost[0].node_id, 1u);
  EXPECT_TRUE(registry.Find(1)->lost);
  EXPECT_TRUE(registry.Tick(4 * kSecond).empty());  // reported once
  lost = registry.Tick(6 * kSecond);
  ASSERT_EQ(lost.size(), 1u);
  EXPECT_EQ(lost[0].node_id, 2u);

  const auto back = registry.OnPacket(Frame(1, 7), "a:1", 10 * kSecond);
  ASSERT_EQ(back.size(), 1u);
  EXPECT_EQ(back[0].kind, RegistryEventKind::kBack);
  EXPECT_FALSE(registry.Find(1)->lost);
  EXPECT_EQ(registry.Find(1)->times_lost, 1u);
  EXPECT_TRUE(registry.Tick(12 * kSecond).empty());
}

TEST(NodeRegistry, AddressChangeAndRestartAreReported) {
  NodeRegistry registry;
  registry.OnPacket(Status(5, 50'000), "10.0.0.5:4000", 0);
  auto events = registry.OnPacket(Status(5, 51'000), "10.0.0.9:4000", kSecond);
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events[0].kind, RegistryEventKind::kAddressChanged);
  EXPECT_EQ(events[0].address, "10.0.0.9:4000");
  EXPECT_EQ(events[0].previous_address, "10.0.0.5:4000");
  EXPECT_EQ(registry.Find(5)->address, "10.0.0.9:4000");
  EXPECT_EQ(registry.Find(5)->address_changes, 1u);

  events = registry.OnPacket(Status(5, 200), "10.0.0.9:4000", 2 * kSecond);
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events[0].kind, RegistryEventKind::kRestarted);
  EXPECT_EQ(registry.Find(5)->restarts, 1u);
  EXPECT_EQ(registry.Find(5)->uptime_ms, 200u);
}

TEST(NodeRegistry, UnattributableDatagramsAreCountedPerSourceWithinBounds) {
  NodeRegistryOptions options;
  options.max_sources = 2;
  options.allowed_nodes = {1, 2};
  NodeRegistry registry(options);
  registry.OnMalformed("evil:1", "not a protocol buffer packet", 0);
  registry.OnMalformed("evil:1", "empty datagram", 1);
  registry.OnPacket(Status(9), "stranger:1", 2);   // not in the installation
  v1::Packet control;
  control.set_version(1);
  control.mutable_control()->mutable_stop();
  registry.OnPacket(control, "otherhub:1", 3);     // hub-to-node traffic arriving here
  registry.OnMalformed("fourth:1", "x", 4);

  EXPECT_EQ(registry.Find(9), nullptr);
  ASSERT_EQ(registry.sources().size(), 2u);
  const SourceCounts& evil = registry.sources().at("evil:1");
  EXPECT_EQ(evil.malformed, 2u);
  EXPECT_EQ(evil.last_reason, "empty datagram");
  EXPECT_EQ(registry.sources().at("stranger:1").unknown, 1u);
  EXPECT_EQ(registry.other_sources().unknown, 1u);
  EXPECT_EQ(registry.other_sources().malformed, 1u);
  EXPECT_EQ(registry.malformed_total(), 3u);
  EXPECT_EQ(registry.unknown_total(), 2u);
}

TEST(NodeRegistry, NodeTableIsBounded) {
  NodeRegistryOptions options;
  options.max_nodes = 3;
  NodeRegistry registry(options);
  for (uint32_t id = 1; id <= 10; ++id) registry.OnPacket(Status(id), "flood:1", id);
  EXPECT_EQ(registry.Nodes().size(), 3u);
  EXPECT_EQ(registry.unknown_total(), 7u);
  EXPECT_EQ(registry.Nodes().front().id, 1u);
}

TEST(NodeRegistry, OptionsAreChecked) {
  NodeRegistryOptions options;
  EXPECT_EQ(options.Check(), "");
  options.allowed_nodes = {0};
  EXPECT_NE(options.Check(), "");
  EXPECT_THROW(NodeRegistry{options}, std::invalid_argument);
}

}  // namespace
}  // namespace mocap::service

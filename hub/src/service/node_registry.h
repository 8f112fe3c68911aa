// The live hub's table of camera nodes, kept from what they send: NodeStatus heartbeats (state,
// firmware, rates, counters, sync health, camera settings) and marker-frame traffic (seen, last
// frame). A node silent for longer than the timeout is marked lost and comes back by itself
// when it is heard again; a node heard from a new address is reported. Datagrams that are
// malformed or come from no known node are counted per source address in a bounded table.
// Pure bookkeeping: the caller decodes datagrams and passes its receive time, nothing here reads
// a clock or a socket. Error policy: outside input never throws; bad options throw
// std::invalid_argument from the constructor.
#pragma once

#include <cstdint>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "mocap.pb.h"

namespace mocap::service {

struct NodeRegistryOptions {
  uint64_t lost_after_ns = 3'000'000'000;  // nodes send status every second: three missed
  size_t max_nodes = 256;                  // beyond this, new node ids count as unknown sources
  size_t max_sources = 64;                 // per-address counters; the rest count as "other"
  std::set<uint32_t> allowed_nodes;        // empty: any node id joins

  // Empty when usable, otherwise why not.
  std::string Check() const;
};

enum class NodeState { kUnknown, kIdle, kRunning, kCameraError };
const char* NodeStateName(NodeState state);  // "unknown", "idle", "running", "camera-error"

struct SyncHealth {
  uint32_t edge_jitter_ns = 0;
  uint32_t unmatched_frames = 0;
  uint32_t missed_edges = 0;
  uint32_t spurious_edges = 0;
};

struct NodeEntry {
  uint32_t id = 0;
  std::string address;           // HOST:PORT the node sends from
  bool lost = false;
  uint64_t first_seen_ns = 0;
  uint64_t last_seen_ns = 0;
  uint64_t times_lost = 0;
  uint64_t address_changes = 0;
  uint64_t restarts = 0;          // status uptime went backwards
  uint64_t datagrams = 0;         // every valid datagram from the node
  uint64_t marker_datagrams = 0;
  bool has_frame = false;
  uint64_t last_frame_number = 0;
  // From the last NodeStatus (has_status false until one arrived).
  bool has_status = false;
  uint64_t last_status_ns = 0;
  NodeState state = NodeState::kUnknown;
  std::string firmware_version;
  uint64_t uptime_ms = 0;
  double fps = 0.0;
  uint32_t detect_time_us_mean = 0;
  uint32_t detect_time_us_max = 0;
  uint64_t frames_captured = 0;
  uint64_t frames_sent = 0;
  uint64_t frames_dropped = 0;
  bool has_temperature = false;
  double temperature_c = 0.0;
  SyncHealth sync;
  uint32_t threshold = 0;
  uint32_t exposure_us = 0;
  uint32_t gain_milli = 0;
  bool exposure_fixed = false;  // recorded frames: exposure and gain say nothing
  uint32_t control_rejected = 0;
  uint32_t auth_rejected = 0;     // hub datagrams the node refused as unauthentic
  uint32_t camera_reopens = 0;
  uint32_t width = 0;
  uint32_t height = 0;
};

// Datagrams the registry could not attribute to a node, per source address.
struct SourceCounts {
  uint64_t malformed = 0;         // refused by the wire rules
  uint64_t unknown = 0;           // valid, but from no node we track
  uint64_t unauthentic = 0;       // refused by the authenticated wire (forged, replayed, plain)
  std::string last_reason;
  uint64_t last_seen_ns = 0;
};

enum class RegistryEventKind { kJoined, kLost, kBack, kAddressChanged, kRestarted };
// "joined", "lost", "back", "address-changed", "restarted"
const char* RegistryEventName(RegistryEventKind kind);

struct RegistryEvent {
  RegistryEventKind kind = RegistryEventKind::kJoined;
  uint32_t node_id = 0;
  uint64_t time_ns = 0;
  std::string address;           // where the node is now
  std::string previous_address;  // kAddressChanged only
};

class NodeRegistry {
 public:
  explicit NodeRegistry(NodeRegistryOptions options = {});

  // A datagram that passed wire::Decode, from `source` at now_ns. Returns what changed.
  std::vector<RegistryEvent> OnPacket(const v1::Packet& packet, const std::string& source,
                                      uint64_t now_ns);
  // A datagram wire::Decode refused, with its reason.
  void OnMalformed(const std::string& source, const std::string& reason, uint64_t now_ns);
  // A datagram the authenticated wire refused, with its reason.
  void OnUnauthentic(const std::string& source, const std::string& reason, uint64_t now_ns);
  // Marks nodes silent since now_ns - lost_after_ns as lost; returns them.
  std::vector<RegistryEvent> Tick(uint64_t now_ns);

  const NodeEntry* Find(uint32_t node_id) const;
  std::vector<NodeEntry> Nodes() const;  // by id
  const std::map<std::string, SourceCounts>& sources() const { return sources_; }
  const SourceCounts& other_sources() const { return other_; }  // beyond max_sources
  uint64_t malformed_total() const { return malformed_total_; }
  uint64_t unknown_total() const { return unknown_total_; }
  uint64_t unauthentic_total() const { return unauthentic_total_; }

 private:
  NodeEntry* Attribute(uint32_t node_id, const std::string& source, uint64_t now_ns,
                       std::vector<RegistryEvent>* events);
  SourceCounts& CountsFor(const std::string& source);
  void CountUnknown(const std::string& source, const std::string& reason, uint64_t now_ns);

  NodeRegistryOptions options_;
  std::map<uint32_t, NodeEntry> nodes_;
  std::map<std::string, SourceCounts> sources_;
  SourceCounts other_;
  uint64_t malformed_total_ = 0, unknown_total_ = 0, unauthentic_total_ = 0;
};

}  // namespace mocap::service

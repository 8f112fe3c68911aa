// Node table bookkeeping (see node_registry.h).
#include "service/node_registry.h"

#include <stdexcept>

namespace mocap::service {
namespace {

NodeState FromWire(v1::NodeState s) {
  switch (s) {
    case v1::NODE_STATE_IDLE: return NodeState::kIdle;
    case v1::NODE_STATE_RUNNING: return NodeState::kRunning;
    case v1::NODE_STATE_CAMERA_ERROR: return NodeState::kCameraError;
    default: return NodeState::kUnknown;
  }
}

// The node id a node-to-hub packet names; 0 for packets nodes never send.
uint32_t SenderId(const v1::Packet& p) {
  switch (p.body_case()) {
    case v1::Packet::kMarkerFrame: return p.marker_frame().node_id();
    case v1::Packet::kNodeStatus: return p.node_status().node_id();
    case v1::Packet::kPreviewChunk: return p.preview_chunk().node_id();
    case v1::Packet::kControlAck: return p.control_ack().node_id();
    default: return 0;
  }
}

void CopyStatus(const v1::NodeStatus& s, uint64_t now_ns, NodeEntry* e) {
  e->has_status = true;
  e->last_status_ns = now_ns;
  e->state = FromWire(s.state());
  e->firmware_version = s.firmware_version();
  e->uptime_ms = s.uptime_ms();
  e->fps = s.fps_milli() / 1000.0;
  e->detect_time_us_mean = s.detect_time_us_mean();
  e->detect_time_us_max = s.detect_time_us_max();
  e->frames_captured = s.frames_captured();
  e->frames_sent = s.frames_sent();
  e->frames_dropped = s.frames_dropped();
  e->has_temperature = s.has_temperature();
  e->temperature_c = s.has_temperature() ? s.temperature_mdeg() / 1000.0 : 0.0;
  e->sync.edge_jitter_ns = s.sync().edge_jitter_ns();
  e->sync.unmatched_frames = s.sync().unmatched_frames();
  e->sync.missed_edges = s.sync().missed_edges();
  e->sync.spurious_edges = s.sync().spurious_edges();
  e->threshold = s.threshold();
  e->exposure_us = s.exposure_us();
  e->gain_milli = s.gain_milli();
  e->exposure_fixed = s.exposure_fixed();
  e->control_rejected = s.control_rejected();
  e->auth_rejected = s.auth_rejected();
  e->camera_reopens = s.camera_reopens();
  e->width = s.width();
  e->height = s.height();
}

}  // namespace

std::string NodeRegistryOptions::Check() const {
  if (lost_after_ns == 0) return "lost_after_ns must be > 0";
  if (max_nodes == 0) return "max_nodes must be > 0";
  if (max_sources == 0) return "max_sources must be > 0";
  if (allowed_nodes.count(0)) return "node id 0 addresses every node and cannot be allowed";
  return {};
}

const char* NodeStateName(NodeState state) {
  switch (state) {
    case NodeState::kIdle: return "idle";
    case NodeState::kRunning: return "running";
    case NodeState::kCameraError: return "camera-error";
    case NodeState::kUnknown: break;
  }
  return "unknown";
}

const char* RegistryEventName(RegistryEventKind kind) {
  switch (kind) {
    case RegistryEventKind::kJoined: return "joined";
    case RegistryEventKind::kLost: return "lost";
    case RegistryEventKind::kBack: return "back";
    case RegistryEventKind::kAddressChanged: return "address-changed";
    case RegistryEventKind::kRestarted: return "restarted";
  }
  return "unknown";
}

NodeRegistry::NodeRegistry(NodeRegistryOptions options) : options_(std::move(options)) {
  const std::string problem = options_.Check();
  if (!problem.empty()) throw std::invalid_argument("node registry: " + problem);
}

SourceCounts& NodeRegistry::CountsFor(const std::string& source) {
  auto it = sources_.find(source);
  if (it != sources_.end()) return it->second;
  if (sources_.size() >= options_.max_sources) return other_;
  return sources_[source];
}

void NodeRegistry::CountUnknown(const std::string& source, const std::string& reason, uint64_t now_ns) {
  SourceCounts& c = CountsFor(source);
  ++c.unknown;
  c.last_reason = reason;
  c.last_seen_ns = now_ns;
  ++unknown_total_;
}

void NodeRegistry::OnMalformed(const std::string& source, const std::string& reason, uint64_t now_ns) {
  SourceCounts& c = CountsFor(source);
  ++c.malformed;
  c.last_reason = reason;
  c.last_seen_ns = now_ns;
  ++malformed_total_;
}

void NodeRegistry::OnUnauthentic(const std::string& source, const std::string& reason, uint64_t now_ns) {
  SourceCounts& c = CountsFor(source);
  ++c.unauthentic;
  c.last_reason = reason;
  c.last_seen_ns = now_ns;
  ++unauthentic_total_;
}

NodeEntry* NodeRegistry::Attribute(uint32_t node_id, const std::string& source, uint64_t now_ns,
                                   std::vector<RegistryEvent>* events) {
  auto it = nodes_.find(node_id);
  if (it == nodes_.end()) {
    if (!options_.allowed_nodes.empty() && !options_.allowed_nodes.count(node_id)) {
      CountUnknown(source, "node " + std::to_string(node_id) + " is not in the installation", now_ns);
      return nullptr;
    }
    if (nodes_.size() >= options_.max_nodes) {
      CountUnknown(source, "node table full", now_ns);
      return nullptr;
    }
    NodeEntry& e = nodes_[node_id];
    e.id = node_id;
    e.address = source;
    e.first_seen_ns = now_ns;
    e.last_seen_ns = now_ns;
    events->push_back({RegistryEventKind::kJoined, node_id, now_ns, source, {}});
    return &e;
  }
  NodeEntry& e = it->second;
  if (e.lost) {
    e.lost = false;
    events->push_back({RegistryEventKind::kBack, node_id, now_ns, source, {}});
  }
  if (e.address != source) {
    ++e.address_changes;
    events->push_back({RegistryEventKind::kAddressChanged, node_id, now_ns, source, e.address});
    e.address = source;
  }
  // A datagram delayed in a queue must not move last_seen back.
  if (now_ns > e.last_seen_ns) e.last_seen_ns = now_ns;
  return &e;
}

std::vector<RegistryEvent> NodeRegistry::OnPacket(const v1::Packet& packet, const std::string& source,
                                                  uint64_t now_ns) {
  std::vector<RegistryEvent> events;
  const uint32_t id = SenderId(packet);
  if (id == 0) {
    CountUnknown(source, "not a node-to-hub packet", now_ns);
    return events;
  }
  NodeEntry* e = Attribute(id, source, now_ns, &events);
  if (!e) return events;
  ++e->datagrams;
  if (packet.has_node_status()) {
    if (e->has_status && packet.node_status().uptime_ms() < e->uptime_ms) {
      ++e->restarts;
      events.push_back({RegistryEventKind::kRestarted, id, now_ns, source, {}});
    }
    CopyStatus(packet.node_status(), now_ns, e);
  } else if (packet.has_marker_frame()) {
    ++e->marker_datagrams;
    const uint64_t frame = packet.marker_frame().frame_number();
    if (!e->has_frame || frame > e->last_frame_number) e->last_frame_number = frame;
    e->has_frame = true;
  }
  return events;
}

std::vector<RegistryEvent> NodeRegistry::Tick(uint64_t now_ns) {
  std::vector<RegistryEvent> events;
  for (auto& [id, e] : nodes_) {
    if (e.lost || now_ns < e.last_seen_ns || now_ns - e.last_seen_ns <= options_.lost_after_ns) continue;
    e.lost = true;
    ++e.times_lost;
    events.push_back({RegistryEventKind::kLost, id, now_ns, e.address, {}});
  }
  return events;
}

const NodeEntry* NodeRegistry::Find(uint32_t node_id) const {
  auto it = nodes_.find(node_id);
  return it == nodes_.end() ? nullptr : &it->second;
}

std::vector<NodeEntry> NodeRegistry::Nodes() const {
  std::vector<NodeEntry> out;
  out.reserve(nodes_.size());
  for (const auto& [id, e] : nodes_) out.push_back(e);
  return out;
}

}  // namespace mocap::service

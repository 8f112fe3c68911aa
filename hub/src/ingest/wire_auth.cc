// The hub's end of the authenticated wire (see wire_auth.h).
#include "ingest/wire_auth.h"

#include <sys/stat.h>

#include <filesystem>
#include <stdexcept>

#include "util/log.h"

namespace mocap {
namespace {

// node-N.key -> N; 0 for any other name.
uint32_t NodeOfFileName(const std::string& name) {
  const std::string prefix = "node-", suffix = ".key";
  if (name.size() <= prefix.size() + suffix.size() || name.compare(0, prefix.size(), prefix) != 0 ||
      name.compare(name.size() - suffix.size(), suffix.size(), suffix) != 0)
    return 0;
  const std::string digits = name.substr(prefix.size(), name.size() - prefix.size() - suffix.size());
  if (digits.empty() || digits.size() > 4 || digits.find_first_not_of("0123456789") != std::string::npos) return 0;
  const unsigned long id = std::stoul(digits);
  return id >= 1 && id <= 4095 ? static_cast<uint32_t>(id) : 0;
}

}  // namespace

void WireAuthOptions::Check() const {
  if (keys_dir.empty() && !insecure_dev)
    throw std::invalid_argument(
        "the wire needs keys: --keys DIR (node-N.key files from `mocap-hub keys new`), or --insecure-dev-wire "
        "for development only");
  if (!keys_dir.empty() && insecure_dev)
    throw std::invalid_argument("--keys and --insecure-dev-wire exclude each other");
  budget.Check();
}

const char* WireRejectionName(WireRejection r) {
  switch (r) {
    case WireRejection::kNone: return "none";
    case WireRejection::kMalformed: return "malformed_envelope";
    case WireRejection::kUnauthenticated: return "unauthenticated";
    case WireRejection::kUnknownNode: return "unknown_node";
    case WireRejection::kUnknownKey: return "unknown_key";
    case WireRejection::kBadTag: return "bad_tag";
    case WireRejection::kWrongDirection: return "wrong_direction";
    case WireRejection::kReplayed: return "replayed";
    case WireRejection::kStale: return "stale";
    case WireRejection::kFuture: return "future";
    case WireRejection::kNodeMismatch: return "node_mismatch";
    case WireRejection::kThrottled: return "throttled";
  }
  return "?";
}

WireAuth::WireAuth(WireAuthOptions options) : options_(std::move(options)), budget_(options_.budget) {
  options_.Check();
  if (options_.insecure_dev) return;
  wire::InitSodium();
  for (auto& [id, file] : LoadDirectory()) {
    Peer& peer = peers_[id];
    peer.file = std::move(file);
    peer.send_key_id = peer.file.keys.front().id;
  }
  fingerprint_ = DirectoryFingerprint();
}

std::map<uint32_t, wire::KeyFile> WireAuth::LoadDirectory() const {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (!fs::is_directory(options_.keys_dir, ec))
    throw std::runtime_error("keys directory " + options_.keys_dir + ": not a directory");
  std::map<uint32_t, wire::KeyFile> files;
  for (const fs::directory_entry& entry : fs::directory_iterator(options_.keys_dir, ec)) {
    const uint32_t id = NodeOfFileName(entry.path().filename().string());
    if (id == 0) continue;
    wire::KeyFile file = wire::ReadKeyFile(entry.path().string());
    if (file.node_id != id)
      throw std::runtime_error(entry.path().string() + ": holds the key of node " + std::to_string(file.node_id));
    files[id] = std::move(file);
  }
  if (ec) throw std::runtime_error("keys directory " + options_.keys_dir + ": " + ec.message());
  return files;
}

std::string WireAuth::DirectoryFingerprint() const {
  namespace fs = std::filesystem;
  std::string print;
  std::error_code ec;
  for (const fs::directory_entry& entry : fs::directory_iterator(options_.keys_dir, ec)) {
    if (NodeOfFileName(entry.path().filename().string()) == 0) continue;
    struct stat st{};
    if (stat(entry.path().c_str(), &st) != 0) continue;
    print += entry.path().filename().string() + ":" + std::to_string(st.st_mtim.tv_sec) + "." +
             std::to_string(st.st_mtim.tv_nsec) + ":" + std::to_string(st.st_size) + ";";
  }
  return print;
}

void WireAuth::ReloadIfChanged(uint64_t now_ns) {
  if (options_.insecure_dev || now_ns < next_reload_check_ns_) return;
  next_reload_check_ns_ = now_ns + 1'000'000'000ull;
  const std::string print = DirectoryFingerprint();
  if (print == fingerprint_) return;
  fingerprint_ = print;
  std::map<uint32_t, wire::KeyFile> files;
  try {
    files = LoadDirectory();
  } catch (const std::exception& e) {
    log::Error("keys not reloaded, the previous keys stay in use: {}", e.what());
    return;
  }
  for (auto it = peers_.begin(); it != peers_.end();) {
    if (!files.count(it->first)) {
      log::Warn("node {}: key file removed, its datagrams are refused from now on", it->first);
      it = peers_.erase(it);
    } else {
      ++it;
    }
  }
  for (auto& [id, file] : files) {
    auto [it, added] = peers_.try_emplace(id);
    Peer& peer = it->second;
    peer.file = std::move(file);
    if (added || !peer.file.Find(peer.send_key_id)) peer.send_key_id = peer.file.keys.front().id;
    std::string ids;
    for (const auto& k : peer.file.keys) ids += (ids.empty() ? "" : ",") + std::to_string(k.id);
    log::Info("node {}: keys {} {}", id, ids, added ? "added" : "reloaded");
  }
}

WireOpened WireAuth::Reject(WireRejection kind, std::string reason, uint32_t node_id) {
  ++rejected_total_;
  ++rejected_[kind];
  auto peer = peers_.find(node_id);
  if (peer != peers_.end()) {
    ++peer->second.counts.rejected;
    ++peer->second.counts.by_kind[kind];
  }
  WireOpened out;
  out.rejection = kind;
  out.reason = std::move(reason);
  out.node_id = node_id;
  return out;
}

WireOpened WireAuth::RejectCounter(wire::ReplayWindow::Verdict verdict, uint32_t node) {
  const std::string who = "node " + std::to_string(node);
  switch (verdict) {
    case wire::ReplayWindow::Verdict::kReplayed: return Reject(WireRejection::kReplayed, who + ": replayed counter", node);
    case wire::ReplayWindow::Verdict::kStale:
      return Reject(WireRejection::kStale, who + ": stale counter (replay, or clocks apart)", node);
    case wire::ReplayWindow::Verdict::kFuture:
      return Reject(WireRejection::kFuture, who + ": counter ahead of the hub's clock", node);
    case wire::ReplayWindow::Verdict::kAccepted: break;
  }
  return Reject(WireRejection::kReplayed, who + ": counter", node);
}

WireOpened WireAuth::Open(const uint8_t* data, size_t size, uint64_t now_ns, const sockaddr_in* source) {
  const bool enveloped = wire::LooksEnveloped(data, size);
  if (options_.insecure_dev) {
    if (enveloped)
      return Reject(WireRejection::kUnauthenticated, "authenticated datagram, but the hub runs --insecure-dev-wire", 0);
    WireOpened out;
    out.ok = true;
    out.payload = data;
    out.payload_size = size;
    return out;
  }
  if (!enveloped) return Reject(WireRejection::kUnauthenticated, "unauthenticated datagram (no envelope)", 0);
  const wire::ParsedEnvelope env = wire::ParseEnvelope(data, size);
  if (!env.ok) return Reject(WireRejection::kMalformed, env.reason, 0);
  const uint32_t node = env.header.node_id;
  auto it = peers_.find(node);
  if (it == peers_.end())
    return Reject(WireRejection::kUnknownNode, "no key for node " + std::to_string(node), 0);
  Peer& peer = it->second;
  const wire::WireKeyEntry* key = peer.file.Find(env.header.key_id);
  if (!key) return Reject(WireRejection::kUnknownKey, "node " + std::to_string(node) + ": unknown key id " +
                                                          std::to_string(env.header.key_id), node);
  // The counter first (a lookup, not a hash): a flood of recorded datagrams is refused before
  // the tag is computed; the window moves only below, once the tag verified.
  using Verdict = wire::ReplayWindow::Verdict;
  if (const Verdict early = peer.window.Check(env.header.counter, now_ns); early != Verdict::kAccepted)
    return RejectCounter(early, node);
  if (source && !budget_.Allow(*source, now_ns))
    return Reject(WireRejection::kThrottled, "node " + std::to_string(node) + ": its source's tag checks spent", node);
  if (!wire::VerifyEnvelopeTag(data, size, key->key))
    return Reject(WireRejection::kBadTag, "node " + std::to_string(node) + ": bad tag (forged, or another key)", node);
  if (env.header.direction != wire::Direction::kToHub)
    return Reject(WireRejection::kWrongDirection, "node " + std::to_string(node) + ": the hub's own datagram sent back",
                  node);
  if (const Verdict verdict = peer.window.Accept(env.header.counter, now_ns); verdict != Verdict::kAccepted)
    return RejectCounter(verdict, node);
  ++peer.counts.accepted;
  if (source) budget_.Trust(*source, now_ns);
  peer.send_key_id = env.header.key_id;  // answer with the key the node uses now (rotation)
  WireOpened out;
  out.ok = true;
  out.node_id = node;
  out.payload = env.payload;
  out.payload_size = env.payload_size;
  return out;
}

void WireAuth::CountNodeMismatch(uint32_t envelope_node) {
  Reject(WireRejection::kNodeMismatch, "", envelope_node);
}

std::vector<uint8_t> WireAuth::Seal(uint32_t node_id, const std::vector<uint8_t>& payload, uint64_t now_ns) {
  if (options_.insecure_dev) return payload;
  auto it = peers_.find(node_id);
  if (it == peers_.end()) return {};
  const wire::WireKeyEntry* key = it->second.file.Find(it->second.send_key_id);
  if (!key) key = &it->second.file.keys.front();
  last_counter_ = wire::NextCounter(last_counter_, now_ns);
  return wire::SealEnvelope({wire::Direction::kToNode, key->id, node_id, last_counter_}, key->key, payload.data(),
                            payload.size());
}

std::vector<std::vector<uint8_t>> WireAuth::SealForEveryNode(const std::vector<uint8_t>& payload, uint64_t now_ns) {
  if (options_.insecure_dev) return {payload};
  std::vector<std::vector<uint8_t>> out;
  for (const auto& entry : peers_) out.push_back(Seal(entry.first, payload, now_ns));
  return out;
}

std::vector<uint32_t> WireAuth::KeyedNodes() const {
  std::vector<uint32_t> ids;
  for (const auto& entry : peers_) ids.push_back(entry.first);
  return ids;
}

uint64_t WireAuth::Rejected(WireRejection kind) const {
  auto it = rejected_.find(kind);
  return it == rejected_.end() ? 0 : it->second;
}

const WireAuth::PeerCounts* WireAuth::Counts(uint32_t node_id) const {
  auto it = peers_.find(node_id);
  return it == peers_.end() ? nullptr : &it->second.counts;
}

nlohmann::json WireAuth::StatusJson() const {
  nlohmann::json by_kind = nlohmann::json::object();
  for (const auto& [kind, n] : rejected_) by_kind[WireRejectionName(kind)] = n;
  nlohmann::json j = {{"mode", options_.insecure_dev ? "insecure-dev" : "authenticated"},
                      {"rejected", rejected_total_},
                      {"rejected_by_kind", by_kind}};
  if (options_.insecure_dev) {
    j["warning"] = "INSECURE: --insecure-dev-wire is set; datagrams are not authenticated and anyone on the "
                   "network can forge frames and steer nodes (development only)";
    return j;
  }
  j["keys_dir"] = options_.keys_dir;
  j["nodes_with_keys"] = peers_.size();
  nlohmann::json nodes = nlohmann::json::object();
  for (const auto& [id, peer] : peers_) {
    nlohmann::json kinds = nlohmann::json::object();
    for (const auto& [kind, n] : peer.counts.by_kind) kinds[WireRejectionName(kind)] = n;
    nodes[std::to_string(id)] = {{"accepted", peer.counts.accepted},
                                 {"rejected", peer.counts.rejected},
                                 {"rejected_by_kind", kinds},
                                 {"send_key_id", peer.send_key_id}};
  }
  j["nodes"] = nodes;
  return j;
}

}  // namespace mocap

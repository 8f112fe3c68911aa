// The hub's end of the authenticated wire, shared by `serve` and `record`: the keys of the
// installation's nodes (one file per node in the keys directory, wire/key_file.h), every
// datagram from a node opened and checked before anything else reads it (envelope, node known,
// key id held, counter fresh and not replayed, tag, direction; the counter is looked up before the
// tag is computed, so a replay flood costs no hashing, and remembered only after), every datagram to a node sealed
// under that node's key with the hub's own strictly increasing counter. Refusals are counted
// per node (for nodes with a key) and in total; they never reach the decoder or the assembler.
//
// Rotation: a node's file lists one or two keys; every listed key is accepted, and the hub
// answers a node with the key id of that node's last authentic datagram (else the file's first
// key), so it follows a node through a change-over by itself. The directory is re-read when a
// file in it changes (checked once a second); a file that no longer parses keeps the old keys
// and is reported.
//
// Development mode (insecure_dev): no keys, plain protocol-v1 datagrams both ways; enveloped
// datagrams are refused. The hub warns at start and /api/status says so.
//
// Threads: one owner (the hub's loop). Error policy: the constructor throws std::runtime_error
// for a missing directory or a bad key file (naming it); outside input never throws.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "ingest/source_budget.h"
#include "wire/datagram_envelope.h"
#include "wire/key_file.h"
#include "wire/replay_window.h"

namespace mocap {

struct WireAuthOptions {
  std::string keys_dir;      // node-N.key files; required unless insecure_dev
  bool insecure_dev = false; // unauthenticated wire: development only
  SourceBudgetOptions budget;  // tag checks per second per source that is not a node's
  // Throws std::invalid_argument when neither or both are set.
  void Check() const;
};

enum class WireRejection {
  kNone,
  kMalformed,        // not an envelope, or its header is broken
  kUnauthenticated,  // a plain packet while keys are required (or an envelope in insecure mode)
  kUnknownNode,      // no key file for the node id it names
  kUnknownKey,       // the node's file holds no key with that id
  kBadTag,           // forged, or sealed with another key
  kWrongDirection,   // a hub->node datagram sent back to the hub
  kReplayed,         // a counter already seen, or below the window
  kStale,            // a counter far older than the hub's clock
  kFuture,           // a counter far ahead of the hub's clock
  kNodeMismatch,     // authentic, but the packet inside speaks for another node
  kThrottled,        // its source (not a node's) spent its budget of tag checks: a flood
};
const char* WireRejectionName(WireRejection r);  // "bad_tag", "replayed", ...

struct WireOpened {
  bool ok = false;
  WireRejection rejection = WireRejection::kNone;
  std::string reason;
  uint32_t node_id = 0;             // from the envelope (0 in insecure mode)
  const uint8_t* payload = nullptr;  // the Packet, inside the datagram
  size_t payload_size = 0;
};

class WireAuth {
 public:
  explicit WireAuth(WireAuthOptions options);

  bool insecure() const { return options_.insecure_dev; }
  // One datagram from the network, at the hub's realtime clock now_ns; from `source` when known
  // (then its tag is checked only within the source's budget, source_budget.h).
  WireOpened Open(const uint8_t* data, size_t size, uint64_t now_ns, const sockaddr_in* source = nullptr);
  // The caller found that an opened packet names another node than its envelope.
  void CountNodeMismatch(uint32_t envelope_node);
  // payload sealed for node_id; empty when there is no key for it. Insecure: payload itself.
  std::vector<uint8_t> Seal(uint32_t node_id, const std::vector<uint8_t>& payload, uint64_t now_ns);
  // One datagram per node with a key (a broadcast announce), or the payload once when insecure.
  std::vector<std::vector<uint8_t>> SealForEveryNode(const std::vector<uint8_t>& payload, uint64_t now_ns);
  bool HasKey(uint32_t node_id) const { return peers_.count(node_id) != 0; }
  std::vector<uint32_t> KeyedNodes() const;
  // Re-reads the keys directory when one of its files changed; at most once a second.
  void ReloadIfChanged(uint64_t now_ns);

  struct PeerCounts {
    uint64_t accepted = 0;
    uint64_t rejected = 0;  // all of the kinds below
    std::map<WireRejection, uint64_t> by_kind;
  };
  uint64_t rejected_total() const { return rejected_total_; }
  uint64_t Rejected(WireRejection kind) const;
  const PeerCounts* Counts(uint32_t node_id) const;
  // {"mode", "keys_dir", "nodes_with_keys", "rejected", "rejected_by_kind", "nodes": {id: ...}}.
  nlohmann::json StatusJson() const;

 private:
  struct Peer {
    wire::KeyFile file;
    uint8_t send_key_id = 0;
    wire::ReplayWindow window;
    PeerCounts counts;
  };
  WireOpened Reject(WireRejection kind, std::string reason, uint32_t node_id);
  WireOpened RejectCounter(wire::ReplayWindow::Verdict verdict, uint32_t node_id);
  std::map<uint32_t, wire::KeyFile> LoadDirectory() const;  // throws std::runtime_error
  std::string DirectoryFingerprint() const;

  WireAuthOptions options_;
  std::map<uint32_t, Peer> peers_;
  SourceBudget budget_;
  uint64_t last_counter_ = 0;
  uint64_t rejected_total_ = 0;
  std::map<WireRejection, uint64_t> rejected_;  // all nodes, and datagrams naming none we know
  uint64_t next_reload_check_ns_ = 0;
  std::string fingerprint_;
};

}  // namespace mocap

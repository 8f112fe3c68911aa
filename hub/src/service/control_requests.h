// Hub-to-node requests and their fate: builds the Control datagrams of a request (node id and
// increasing sequence numbers filled in), tracks them until every datagram is answered by the
// node's ControlAck, and reports each request once: applied, ignored (nothing changed),
// rejected with the node's reason, or timed out after a deadline (a node that does not answer
// is never waited for forever).
//
// Retransmission: UDP may lose a Control or its ack, so an unanswered datagram is sent again with
// the same sequence after retransmit_after_ns until the deadline. That is safe because every
// command is idempotent on the node: commands set state, a mask chunk already stored is
// answered "ignored", and a repeated preview request only renders one more preview, which the
// preview assembler replaces.
//
// A multi-datagram request (a mask image in chunks) takes consecutive sequences, as the node's
// mask assembly requires (proto/mocap.proto); it is applied when every datagram is applied or
// ignored, and rejected as soon as one is rejected.
//
// Pure: time is a parameter, the caller sends the returned packets to the node's address.
// Error policy: outside input (acks) never throws; a request that breaks the wire rules or
// names node 0 is a programming error (std::invalid_argument); a full table is a refusal with a
// reason, not an exception.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "mocap.pb.h"

namespace mocap::service {

struct ControlRequestsOptions {
  uint64_t timeout_ns = 2'000'000'000;          // unanswered this long: reported timed out
  uint64_t retransmit_after_ns = 250'000'000;   // resend an unanswered datagram; 0 = never
  size_t max_pending = 256;                     // requests in flight over all nodes
  size_t max_datagrams_per_request = 64;        // a mask image's chunks (the node takes 64)
  // serve seeds it from the clock, so that a restarted hub does not reuse the sequences of a
  // mask image a node may still hold half-assembled.
  uint32_t first_sequence = 1;

  // Empty when usable, otherwise why not.
  std::string Check() const;
};

enum class RequestOutcome { kApplied, kIgnored, kRejected, kTimedOut };
const char* RequestOutcomeName(RequestOutcome outcome);  // "applied", "ignored", "rejected", "timed-out"

struct RequestResult {
  uint64_t request_id = 0;
  uint32_t node_id = 0;
  RequestOutcome outcome = RequestOutcome::kApplied;
  std::string reason;             // the node's (rejected, ignored) or ours (timed out)
  uint64_t submitted_ns = 0;
  uint64_t finished_ns = 0;
  size_t datagrams = 0;
  size_t answered = 0;            // datagrams acknowledged when it finished
  uint32_t retransmissions = 0;
};

struct SubmitResult {
  bool ok = false;
  std::string error;              // why it was refused when !ok
  uint64_t request_id = 0;
  std::vector<v1::Packet> send;   // to the node, now, in order
};

class ControlRequests {
 public:
  explicit ControlRequests(ControlRequestsOptions options = {});

  // One request to node_id (not 0) of one command per datagram; each command's node_id and
  // sequence are overwritten.
  SubmitResult Submit(uint32_t node_id, const std::vector<v1::Control>& commands, uint64_t now_ns);
  // An ack from a node. Returns the request it finished, if it finished one.
  std::optional<RequestResult> OnAck(const v1::ControlAck& ack, uint64_t now_ns);

  struct TickResult {
    std::vector<v1::Packet> resend;
    std::vector<RequestResult> finished;  // timed out
  };
  TickResult Tick(uint64_t now_ns);
  // When Tick next has something to do; nullopt when nothing is pending.
  std::optional<uint64_t> NextDeadline() const;

  size_t pending() const { return pending_.size(); }
  // Acks matching no unanswered datagram: late, duplicated, or for a finished request.
  uint64_t stray_acks() const { return stray_acks_; }

 private:
  struct Part {
    v1::Packet packet;
    bool answered = false;
    uint64_t last_sent_ns = 0;
  };
  struct Pending {
    RequestResult result;
    std::vector<Part> parts;
    bool any_applied = false;
  };
  RequestResult Finish(std::map<uint64_t, Pending>::iterator it, RequestOutcome outcome,
                       std::string reason, uint64_t now_ns);

  ControlRequestsOptions options_;
  uint32_t next_sequence_;
  uint64_t next_request_id_ = 1;
  std::map<uint64_t, Pending> pending_;                                  // by request id
  std::map<std::pair<uint32_t, uint32_t>, std::pair<uint64_t, size_t>> parts_;  // (node, seq) -> (request, part)
  uint64_t stray_acks_ = 0;
};

}  // namespace mocap::service

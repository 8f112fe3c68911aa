// Control request tracking (see control_requests.h).
#include "service/control_requests.h"

#include <stdexcept>

#include "wire/limits.h"
#include "wire/packet.h"

namespace mocap::service {

std::string ControlRequestsOptions::Check() const {
  if (timeout_ns == 0) return "timeout_ns must be > 0";
  if (retransmit_after_ns >= timeout_ns) return "retransmit_after_ns must be below timeout_ns";
  if (max_pending == 0) return "max_pending must be > 0";
  if (max_datagrams_per_request == 0) return "max_datagrams_per_request must be > 0";
  return {};
}

const char* RequestOutcomeName(RequestOutcome outcome) {
  switch (outcome) {
    case RequestOutcome::kApplied: return "applied";
    case RequestOutcome::kIgnored: return "ignored";
    case RequestOutcome::kRejected: return "rejected";
    case RequestOutcome::kTimedOut: return "timed-out";
  }
  return "unknown";
}

ControlRequests::ControlRequests(ControlRequestsOptions options)
    : options_(options), next_sequence_(options.first_sequence) {
  const std::string problem = options_.Check();
  if (!problem.empty()) throw std::invalid_argument("control requests: " + problem);
}

SubmitResult ControlRequests::Submit(uint32_t node_id, const std::vector<v1::Control>& commands,
                                     uint64_t now_ns) {
  if (node_id == 0) throw std::invalid_argument("control request: node 0 is not one node");
  if (commands.empty()) throw std::invalid_argument("control request: no command");
  if (commands.size() > options_.max_datagrams_per_request)
    throw std::invalid_argument("control request: " + std::to_string(commands.size()) + " datagrams, at most " +
                                std::to_string(options_.max_datagrams_per_request));
  SubmitResult out;
  if (pending_.size() >= options_.max_pending) {
    out.error = "too many control requests in flight (" + std::to_string(pending_.size()) + ")";
    return out;
  }
  Pending p;
  p.result.request_id = next_request_id_++;
  p.result.node_id = node_id;
  p.result.submitted_ns = now_ns;
  p.result.datagrams = commands.size();
  for (const v1::Control& command : commands) {
    Part part;
    part.packet.set_version(wire::kProtocolVersion);
    *part.packet.mutable_control() = command;
    part.packet.mutable_control()->set_node_id(node_id);
    part.packet.mutable_control()->set_sequence(next_sequence_ + static_cast<uint32_t>(p.parts.size()));
    const std::string problem = wire::Validate(part.packet);
    if (!problem.empty()) throw std::invalid_argument("control request: " + problem);
    part.last_sent_ns = now_ns;
    p.parts.push_back(std::move(part));
  }
  next_sequence_ += static_cast<uint32_t>(p.parts.size());
  for (size_t i = 0; i < p.parts.size(); ++i) {
    parts_[{node_id, p.parts[i].packet.control().sequence()}] = {p.result.request_id, i};
    out.send.push_back(p.parts[i].packet);
  }
  out.ok = true;
  out.request_id = p.result.request_id;
  pending_.emplace(p.result.request_id, std::move(p));
  return out;
}

RequestResult ControlRequests::Finish(std::map<uint64_t, Pending>::iterator it, RequestOutcome outcome,
                                      std::string reason, uint64_t now_ns) {
  Pending& p = it->second;
  for (const Part& part : p.parts) parts_.erase({p.result.node_id, part.packet.control().sequence()});
  RequestResult r = std::move(p.result);
  r.outcome = outcome;
  r.reason = std::move(reason);
  r.finished_ns = now_ns;
  pending_.erase(it);
  return r;
}

std::optional<RequestResult> ControlRequests::OnAck(const v1::ControlAck& ack, uint64_t now_ns) {
  auto where = parts_.find({ack.node_id(), ack.sequence()});
  if (where == parts_.end()) {
    ++stray_acks_;
    return std::nullopt;
  }
  auto it = pending_.find(where->second.first);
  Pending& p = it->second;
  Part& part = p.parts[where->second.second];
  if (part.answered) {
    ++stray_acks_;  // the answer to a retransmission of an answered datagram
    return std::nullopt;
  }
  part.answered = true;
  ++p.result.answered;
  switch (ack.result()) {
    case v1::CONTROL_RESULT_REJECTED:
      return Finish(it, RequestOutcome::kRejected, ack.reason(), now_ns);
    case v1::CONTROL_RESULT_APPLIED:
      p.any_applied = true;
      break;
    default:
      if (p.result.reason.empty()) p.result.reason = ack.reason();
      break;
  }
  if (p.result.answered < p.parts.size()) return std::nullopt;
  if (p.any_applied) return Finish(it, RequestOutcome::kApplied, {}, now_ns);
  std::string reason = p.result.reason;
  return Finish(it, RequestOutcome::kIgnored, std::move(reason), now_ns);
}

ControlRequests::TickResult ControlRequests::Tick(uint64_t now_ns) {
  TickResult out;
  for (auto it = pending_.begin(); it != pending_.end();) {
    Pending& p = it->second;
    if (now_ns >= p.result.submitted_ns + options_.timeout_ns) {
      const std::string reason = "node " + std::to_string(p.result.node_id) + " answered " +
                                 std::to_string(p.result.answered) + " of " + std::to_string(p.parts.size()) +
                                 " datagrams within " + std::to_string(options_.timeout_ns / 1'000'000) + " ms";
      out.finished.push_back(Finish(it++, RequestOutcome::kTimedOut, reason, now_ns));
      continue;
    }
    if (options_.retransmit_after_ns > 0) {
      for (Part& part : p.parts) {
        if (part.answered || now_ns < part.last_sent_ns + options_.retransmit_after_ns) continue;
        part.last_sent_ns = now_ns;
        ++p.result.retransmissions;
        out.resend.push_back(part.packet);
      }
    }
    ++it;
  }
  return out;
}

std::optional<uint64_t> ControlRequests::NextDeadline() const {
  std::optional<uint64_t> next;
  auto consider = [&next](uint64_t t) {
    if (!next || t < *next) next = t;
  };
  for (const auto& [id, p] : pending_) {
    consider(p.result.submitted_ns + options_.timeout_ns);
    if (options_.retransmit_after_ns == 0) continue;
    for (const Part& part : p.parts)
      if (!part.answered) consider(part.last_sent_ns + options_.retransmit_after_ns);
  }
  return next;
}

}  // namespace mocap::service

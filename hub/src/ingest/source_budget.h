// How many costly checks (the envelope's tag: an HMAC) the hub spends per second on datagrams
// from one source address, so that a flood of plausible datagrams from an attacker's address
// cannot starve the nodes of the loop (issue 34, floods). A source that sent an authentic
// datagram within `trusted_for_ns` is a node's and is never limited; any other source gets a
// token bucket of `checks_per_s` (burst as large), and sources beyond `max_sources` share one
// bucket. A datagram over its budget is refused before its tag is computed (counted as
// "throttled"). Someone who forges a node's own source address is checked in full: the budget
// protects the loop's time, the tag still decides what is authentic.
// Pure: time passed in; one owner (the hub's loop).
#pragma once

#include <netinet/in.h>

#include <cstddef>
#include <cstdint>
#include <unordered_map>

namespace mocap {

struct SourceBudgetOptions {
  double checks_per_s = 2000.0;          // tag checks per second per untrusted source
  uint64_t trusted_for_ns = 10'000'000'000;  // an authentic datagram trusts its source this long
  size_t max_sources = 1024;             // sources with a bucket of their own
  // Throws std::invalid_argument naming the value refused.
  void Check() const;
};

class SourceBudget {
 public:
  explicit SourceBudget(SourceBudgetOptions options = {});
  // Whether a datagram from `source` may have its tag checked at now_ns (takes a token).
  bool Allow(const sockaddr_in& source, uint64_t now_ns);
  // The datagram from `source` was authentic: the source is trusted from now on.
  void Trust(const sockaddr_in& source, uint64_t now_ns);
  size_t sources() const { return entries_.size(); }

 private:
  struct Entry {
    double tokens = 0.0;
    uint64_t refilled_ns = 0;
    uint64_t trusted_until_ns = 0;
    uint64_t last_seen_ns = 0;
  };
  static uint64_t KeyOf(const sockaddr_in& source);
  Entry& EntryFor(const sockaddr_in& source, uint64_t now_ns);
  bool Take(Entry& entry, uint64_t now_ns) const;
  void Evict(uint64_t now_ns);

  SourceBudgetOptions options_;
  std::unordered_map<uint64_t, Entry> entries_;
  Entry shared_;  // every source beyond max_sources
};

}  // namespace mocap

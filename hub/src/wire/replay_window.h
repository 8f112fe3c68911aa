// Replay protection for one sender's counters, hub side (the node keeps the same rule with 64
// slots in firmware/wire/envelope.h): the counters of the last `slots` datagrams accepted are
// remembered, so reordering up to that depth is tolerated; once full, anything at or below the
// smallest remembered counter is refused, and so is a counter already seen or further than
// kMaxCounterSkewNs from the receiver's clock. Call Accept only after the tag verified, so that
// forged datagrams can never move the window (Check, which moves nothing, may come before). Pure: the caller passes the clock.
#pragma once

#include <cstddef>
#include <cstdint>
#include <set>

namespace mocap::wire {

class ReplayWindow {
 public:
  explicit ReplayWindow(size_t slots = 512) : slots_(slots < 1 ? 1 : slots) {}

  enum class Verdict { kAccepted, kReplayed, kStale, kFuture };
  // Remembers counter when accepted.
  Verdict Accept(uint64_t counter, uint64_t now_ns);
  // Accept's verdict without remembering anything: a receiver refuses a replayed or stale
  // counter with it before the costly tag check (a flood of recorded datagrams then costs a
  // lookup each), and calls Accept once the tag verified.
  Verdict Check(uint64_t counter, uint64_t now_ns) const;
  size_t remembered() const { return seen_.size(); }

 private:
  size_t slots_;
  std::set<uint64_t> seen_;
};

const char* VerdictName(ReplayWindow::Verdict verdict);  // "accepted", "replayed", "stale", "future"

}  // namespace mocap::wire

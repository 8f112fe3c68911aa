// Replay window (see replay_window.h).
#include "wire/replay_window.h"

#include "wire/datagram_envelope.h"

namespace mocap::wire {

ReplayWindow::Verdict ReplayWindow::Check(uint64_t counter, uint64_t now_ns) const {
  if (counter > now_ns + kMaxCounterSkewNs) return Verdict::kFuture;
  if (counter + kMaxCounterSkewNs < now_ns) return Verdict::kStale;
  if (seen_.size() >= slots_ && counter <= *seen_.begin()) return Verdict::kReplayed;
  if (seen_.count(counter)) return Verdict::kReplayed;
  return Verdict::kAccepted;
}

ReplayWindow::Verdict ReplayWindow::Accept(uint64_t counter, uint64_t now_ns) {
  const Verdict verdict = Check(counter, now_ns);
  if (verdict != Verdict::kAccepted) return verdict;
  seen_.insert(counter);
  if (seen_.size() > slots_) seen_.erase(seen_.begin());
  return Verdict::kAccepted;
}

const char* VerdictName(ReplayWindow::Verdict verdict) {
  switch (verdict) {
    case ReplayWindow::Verdict::kAccepted: return "accepted";
    case ReplayWindow::Verdict::kReplayed: return "replayed";
    case ReplayWindow::Verdict::kStale: return "stale";
    case ReplayWindow::Verdict::kFuture: return "future";
  }
  return "?";
}

}  // namespace mocap::wire

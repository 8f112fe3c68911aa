// Per-source budget of tag checks (see source_budget.h).
#include "ingest/source_budget.h"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <stdexcept>
#include <string>

namespace mocap {

void SourceBudgetOptions::Check() const {
  if (!(checks_per_s >= 1.0) || !std::isfinite(checks_per_s))
    throw std::invalid_argument("source budget: checks_per_s " + std::to_string(checks_per_s) + " must be >= 1");
  if (max_sources == 0) throw std::invalid_argument("source budget: max_sources 0 must be >= 1");
}

SourceBudget::SourceBudget(SourceBudgetOptions options) : options_((options.Check(), options)) {
  shared_.tokens = options_.checks_per_s;
}

uint64_t SourceBudget::KeyOf(const sockaddr_in& source) {
  return (uint64_t(source.sin_addr.s_addr) << 16) | source.sin_port;
}

void SourceBudget::Evict(uint64_t now_ns) {
  // Sources silent for as long as trust lasts, and not trusted, make room.
  for (auto it = entries_.begin(); it != entries_.end();) {
    const bool idle = now_ns > it->second.last_seen_ns + options_.trusted_for_ns;
    it = idle && now_ns >= it->second.trusted_until_ns ? entries_.erase(it) : std::next(it);
  }
}

SourceBudget::Entry& SourceBudget::EntryFor(const sockaddr_in& source, uint64_t now_ns) {
  const uint64_t key = KeyOf(source);
  auto it = entries_.find(key);
  if (it == entries_.end()) {
    if (entries_.size() >= options_.max_sources) Evict(now_ns);
    if (entries_.size() >= options_.max_sources) return shared_;
    Entry fresh;
    fresh.tokens = options_.checks_per_s;
    fresh.refilled_ns = now_ns;
    it = entries_.emplace(key, fresh).first;
  }
  it->second.last_seen_ns = now_ns;
  return it->second;
}

bool SourceBudget::Take(Entry& e, uint64_t now_ns) const {
  if (now_ns > e.refilled_ns) {
    e.tokens = std::min(options_.checks_per_s, e.tokens + double(now_ns - e.refilled_ns) * 1e-9 * options_.checks_per_s);
    e.refilled_ns = now_ns;
  }
  if (e.tokens < 1.0) return false;
  e.tokens -= 1.0;
  return true;
}

bool SourceBudget::Allow(const sockaddr_in& source, uint64_t now_ns) {
  Entry& e = EntryFor(source, now_ns);
  if (&e != &shared_ && now_ns < e.trusted_until_ns) return true;
  return Take(e, now_ns);
}

void SourceBudget::Trust(const sockaddr_in& source, uint64_t now_ns) {
  Entry& e = EntryFor(source, now_ns);
  if (&e != &shared_) e.trusted_until_ns = now_ns + options_.trusted_for_ns;
}

}  // namespace mocap

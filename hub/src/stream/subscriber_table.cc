// UDP stream subscriptions (see subscriber_table.h).
#include "stream/subscriber_table.h"

#include <algorithm>

namespace mocap::stream {
namespace {

bool Same(const sockaddr_in& a, const sockaddr_in& b) {
  return a.sin_addr.s_addr == b.sin_addr.s_addr && a.sin_port == b.sin_port;
}

}  // namespace

bool SubscriberTable::Subscribe(const sockaddr_in& from, uint32_t parts, uint64_t now_ns) {
  for (StreamSubscriber& s : subscribers_) {
    if (!Same(s.address, from)) continue;
    s.parts = parts;
    s.expires_ns = now_ns + lifetime_ns_;
    return true;
  }
  if (subscribers_.size() >= max_) return false;
  subscribers_.push_back({from, parts, now_ns + lifetime_ns_});
  return true;
}

void SubscriberTable::Unsubscribe(const sockaddr_in& from) {
  subscribers_.erase(std::remove_if(subscribers_.begin(), subscribers_.end(),
                                    [&](const StreamSubscriber& s) { return Same(s.address, from); }),
                     subscribers_.end());
}

size_t SubscriberTable::Expire(uint64_t now_ns) {
  const size_t before = subscribers_.size();
  subscribers_.erase(std::remove_if(subscribers_.begin(), subscribers_.end(),
                                    [&](const StreamSubscriber& s) { return s.expires_ns <= now_ns; }),
                     subscribers_.end());
  return before - subscribers_.size();
}

}  // namespace mocap::stream

// Who receives the UDP stream: one entry per client address with the parts it asked for and
// when its subscription runs out unless renewed. Bounded; pure (the caller gives the time).
#pragma once

#include <netinet/in.h>

#include <cstdint>
#include <vector>

namespace mocap::stream {

struct StreamSubscriber {
  sockaddr_in address{};
  uint32_t parts = 0;
  uint64_t expires_ns = 0;
};

class SubscriberTable {
 public:
  SubscriberTable(size_t max_subscribers, uint64_t lifetime_ns)
      : max_(max_subscribers), lifetime_ns_(lifetime_ns) {}

  // Adds or renews; false when the table is full and `from` is new.
  bool Subscribe(const sockaddr_in& from, uint32_t parts, uint64_t now_ns);
  void Unsubscribe(const sockaddr_in& from);
  // Drops the subscriptions that ran out; returns how many.
  size_t Expire(uint64_t now_ns);
  const std::vector<StreamSubscriber>& subscribers() const { return subscribers_; }

 private:
  const size_t max_;
  const uint64_t lifetime_ns_;
  std::vector<StreamSubscriber> subscribers_;
};

}  // namespace mocap::stream

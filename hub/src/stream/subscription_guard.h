// Who may subscribe to the UDP stream: only an address that receives there. A Subscribe without
// a valid cookie is answered with a challenge (the cookie: BLAKE2b keyed with a secret of this
// process over the source address and a 10 s period, so nothing is stored per stranger) and
// only a Subscribe that echoes it subscribes; a forged source never sees the cookie. Challenges
// are rate-limited per source IP (a token bucket per address, at most
// max_sources tracked, the stalest forgotten first), so a flood of forged requests buys at most
// a trickle of small answers, none larger than the request that caused it. Pure: time passed in.
#pragma once

#include <netinet/in.h>

#include <array>
#include <cstdint>
#include <string>
#include <unordered_map>

namespace mocap::stream {

struct SubscriptionGuardOptions {
  double period_s = 10.0;        // a cookie is valid in its period and the next
  double requests_per_s = 20.0;  // challenges per source IP (renewals with a valid cookie are free)
  double burst = 64.0;
  size_t max_sources = 4096;

  // Throws std::invalid_argument naming the bad option.
  void Check() const;
};

class SubscriptionGuard {
 public:
  using Secret = std::array<uint8_t, 32>;

  // A random secret from libsodium's CSPRNG.
  explicit SubscriptionGuard(SubscriptionGuardOptions options = {});
  SubscriptionGuard(SubscriptionGuardOptions options, const Secret& secret);

  // The cookie for `from` now (16 bytes).
  std::string Cookie(const sockaddr_in& from, uint64_t now_ns) const;
  // Whether `cookie` is the one of `from` in this period or the one before.
  bool Valid(const sockaddr_in& from, const std::string& cookie, uint64_t now_ns) const;
  // Takes one request from `from`'s bucket; false when its source is over its rate.
  bool Admit(const sockaddr_in& from, uint64_t now_ns);
  size_t sources() const { return buckets_.size(); }

 private:
  std::string CookieOf(const sockaddr_in& from, uint64_t period) const;

  struct Bucket {
    double tokens = 0.0;
    uint64_t last_ns = 0;
  };
  SubscriptionGuardOptions options_;
  Secret secret_{};
  std::unordered_map<uint32_t, Bucket> buckets_;
};

}  // namespace mocap::stream

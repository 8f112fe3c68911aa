// Who may subscribe to the UDP stream (see subscription_guard.h).
#include "stream/subscription_guard.h"

#include <sodium.h>

#include <algorithm>
#include <stdexcept>

namespace mocap::stream {
namespace {

constexpr size_t kCookieBytes = 16;

}  // namespace

void SubscriptionGuardOptions::Check() const {
  if (!(period_s >= 1.0 && period_s <= 3600.0)) throw std::invalid_argument("stream cookie period must be 1..3600 s");
  if (!(requests_per_s > 0.0 && requests_per_s <= 1e6))
    throw std::invalid_argument("stream requests per second per source must be in (0, 1e6]");
  if (!(burst >= 1.0 && burst <= 1e6)) throw std::invalid_argument("stream request burst must be 1..1e6");
  if (max_sources == 0) throw std::invalid_argument("stream sources tracked must be > 0");
}

SubscriptionGuard::SubscriptionGuard(SubscriptionGuardOptions options) : options_((options.Check(), options)) {
  if (sodium_init() < 0) throw std::runtime_error("libsodium cannot be initialised");
  randombytes_buf(secret_.data(), secret_.size());
}

SubscriptionGuard::SubscriptionGuard(SubscriptionGuardOptions options, const Secret& secret)
    : options_((options.Check(), options)), secret_(secret) {
  if (sodium_init() < 0) throw std::runtime_error("libsodium cannot be initialised");
}

std::string SubscriptionGuard::CookieOf(const sockaddr_in& from, uint64_t period) const {
  uint8_t input[14];
  std::copy_n(reinterpret_cast<const uint8_t*>(&from.sin_addr.s_addr), 4, input);
  std::copy_n(reinterpret_cast<const uint8_t*>(&from.sin_port), 2, input + 4);
  for (int i = 0; i < 8; ++i) input[6 + i] = static_cast<uint8_t>(period >> (8 * i));
  std::string cookie(kCookieBytes, '\0');
  crypto_generichash(reinterpret_cast<unsigned char*>(cookie.data()), cookie.size(), input, sizeof input,
                     secret_.data(), secret_.size());
  return cookie;
}

std::string SubscriptionGuard::Cookie(const sockaddr_in& from, uint64_t now_ns) const {
  return CookieOf(from, now_ns / static_cast<uint64_t>(options_.period_s * 1e9));
}

bool SubscriptionGuard::Valid(const sockaddr_in& from, const std::string& cookie, uint64_t now_ns) const {
  if (cookie.size() != kCookieBytes) return false;
  const uint64_t period = now_ns / static_cast<uint64_t>(options_.period_s * 1e9);
  for (const uint64_t p : {period, period - 1}) {
    const std::string expected = CookieOf(from, p);
    if (sodium_memcmp(expected.data(), cookie.data(), kCookieBytes) == 0) return true;
  }
  return false;
}

bool SubscriptionGuard::Admit(const sockaddr_in& from, uint64_t now_ns) {
  const uint32_t ip = from.sin_addr.s_addr;
  auto it = buckets_.find(ip);
  if (it == buckets_.end()) {
    if (buckets_.size() >= options_.max_sources) {
      // The stalest source goes (a full bucket is as good as a forgotten one).
      const auto stalest = std::min_element(buckets_.begin(), buckets_.end(), [](const auto& a, const auto& b) {
        return a.second.last_ns < b.second.last_ns;
      });
      buckets_.erase(stalest);
    }
    it = buckets_.emplace(ip, Bucket{options_.burst, now_ns}).first;
  }
  Bucket& b = it->second;
  if (now_ns > b.last_ns) {
    b.tokens = std::min(options_.burst, b.tokens + static_cast<double>(now_ns - b.last_ns) * 1e-9 * options_.requests_per_s);
    b.last_ns = now_ns;
  }
  if (b.tokens < 1.0) return false;
  b.tokens -= 1.0;
  return true;
}

}  // namespace mocap::stream

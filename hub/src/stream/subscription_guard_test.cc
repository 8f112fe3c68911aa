// Stream subscription cookies and per-source rates (subscription_guard.h).
#include "stream/subscription_guard.h"

#include <arpa/inet.h>

#include <gtest/gtest.h>

namespace mocap::stream {
namespace {

sockaddr_in Address(const char* ip, uint16_t port) {
  sockaddr_in a{};
  a.sin_family = AF_INET;
  inet_pton(AF_INET, ip, &a.sin_addr);
  a.sin_port = htons(port);
  return a;
}

constexpr uint64_t kSecond = 1'000'000'000;

TEST(SubscriptionGuard, ACookieBelongsToItsAddressAndPeriod) {
  SubscriptionGuard::Secret secret{};
  secret[0] = 7;
  SubscriptionGuard guard({}, secret);
  const sockaddr_in client = Address("10.0.0.5", 4000);
  const std::string cookie = guard.Cookie(client, 100 * kSecond);
  EXPECT_EQ(cookie.size(), 16u);
  EXPECT_TRUE(guard.Valid(client, cookie, 100 * kSecond));
  EXPECT_TRUE(guard.Valid(client, cookie, 119 * kSecond));   // the next period still
  EXPECT_FALSE(guard.Valid(client, cookie, 120 * kSecond));  // two periods on: stale
  EXPECT_FALSE(guard.Valid(Address("10.0.0.5", 4001), cookie, 100 * kSecond));
  EXPECT_FALSE(guard.Valid(Address("10.0.0.6", 4000), cookie, 100 * kSecond));
  EXPECT_FALSE(guard.Valid(client, "", 100 * kSecond));
  EXPECT_FALSE(guard.Valid(client, cookie.substr(0, 15), 100 * kSecond));
  // Another process's secret: another cookie.
  secret[0] = 8;
  EXPECT_FALSE(SubscriptionGuard({}, secret).Valid(client, cookie, 100 * kSecond));
  EXPECT_NE(SubscriptionGuard().Cookie(client, 0), SubscriptionGuard().Cookie(client, 0));
}

TEST(SubscriptionGuard, EachSourceHasItsOwnRate) {
  SubscriptionGuardOptions o;
  o.requests_per_s = 10;
  o.burst = 5;
  o.max_sources = 2;
  SubscriptionGuard guard(o);
  const sockaddr_in a = Address("10.0.0.1", 1), b = Address("10.0.0.2", 1);
  int admitted = 0;
  for (int i = 0; i < 50; ++i) admitted += guard.Admit(a, kSecond);
  EXPECT_EQ(admitted, 5);
  EXPECT_TRUE(guard.Admit(b, kSecond));              // a's flood costs b nothing
  EXPECT_TRUE(guard.Admit(a, kSecond + kSecond / 10));  // refilled at 10/s
  EXPECT_FALSE(guard.Admit(a, kSecond + kSecond / 10));
  // A third source pushes out the stalest (b), within max_sources.
  EXPECT_TRUE(guard.Admit(Address("10.0.0.3", 1), 2 * kSecond));
  EXPECT_EQ(guard.sources(), 2u);
  EXPECT_THROW(SubscriptionGuard(SubscriptionGuardOptions{10, 0, 1, 1}), std::invalid_argument);
}

}  // namespace
}  // namespace mocap::stream

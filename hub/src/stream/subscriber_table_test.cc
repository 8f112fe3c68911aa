// Subscriptions: renewed by the same address, run out when not renewed, bounded.
#include "stream/subscriber_table.h"

#include <arpa/inet.h>

#include <gtest/gtest.h>

namespace mocap::stream {
namespace {

sockaddr_in Address(uint16_t port) {
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_port = htons(port);
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  return a;
}

TEST(SubscriberTable, RenewExpireAndBound) {
  SubscriberTable table(2, 5'000);
  EXPECT_TRUE(table.Subscribe(Address(1000), 1, 0));
  EXPECT_TRUE(table.Subscribe(Address(1001), 3, 0));
  EXPECT_FALSE(table.Subscribe(Address(1002), 1, 0));  // full
  EXPECT_TRUE(table.Subscribe(Address(1000), 2, 4'000));  // a renewal is never refused
  ASSERT_EQ(table.subscribers().size(), 2u);
  EXPECT_EQ(table.subscribers()[0].parts, 2u);
  EXPECT_EQ(table.Expire(5'000), 1u);  // 1001 ran out, 1000 was renewed
  ASSERT_EQ(table.subscribers().size(), 1u);
  EXPECT_EQ(ntohs(table.subscribers()[0].address.sin_port), 1000);
  EXPECT_TRUE(table.Subscribe(Address(1002), 1, 5'000));  // room again
  table.Unsubscribe(Address(1000));
  table.Unsubscribe(Address(4242));  // unknown: nothing happens
  ASSERT_EQ(table.subscribers().size(), 1u);
  EXPECT_EQ(ntohs(table.subscribers()[0].address.sin_port), 1002);
  EXPECT_EQ(table.Expire(10'000), 1u);
  EXPECT_TRUE(table.subscribers().empty());
}

}  // namespace
}  // namespace mocap::stream

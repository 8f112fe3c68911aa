// UDP socket on loopback: bind, receive whole datagrams at their length, timeouts, sender.
#include "ingest/udp_socket.h"

#include <arpa/inet.h>

#include <stdexcept>

#include <gtest/gtest.h>

namespace mocap {
namespace {

HostPort Loopback(uint16_t port) { return HostPort{"127.0.0.1", port}; }

TEST(UdpSocket, DrainTakesWhatIsQueuedUpToItsBound) {
  UdpSocket receiver, sender;
  receiver.Bind(Loopback(0));
  sender.Bind(Loopback(0));
  for (uint8_t i = 0; i < 5; ++i) ASSERT_TRUE(sender.SendTo(Loopback(receiver.port()), {i}));
  std::vector<uint8_t> got;
  const auto keep = [&got](const Datagram& d) { got.push_back(d.bytes.at(0)); };
  EXPECT_EQ(receiver.Drain(1000, 3, keep), 3u);  // the bound: the rest waits for the next turn
  EXPECT_EQ(receiver.Drain(1000, 10, keep), 2u);
  EXPECT_EQ(got, (std::vector<uint8_t>{0, 1, 2, 3, 4}));
  EXPECT_EQ(receiver.Drain(0, 10, keep), 0u);  // nothing queued, no wait
}

// More than one recvmmsg batch, of mixed lengths: each whole, in order, with its sender and time.
TEST(UdpSocket, DrainCrossesBatchesKeepingEachDatagramWhole) {
  UdpSocket receiver, sender;
  receiver.Bind(Loopback(0));
  sender.Bind(Loopback(0));
  const size_t count = 3 * UdpSocket::kBatch + 5;
  for (size_t i = 0; i < count; ++i)
    ASSERT_TRUE(sender.SendTo(Loopback(receiver.port()), std::vector<uint8_t>(1 + (i * 37) % 3000, uint8_t(i))));
  size_t i = 0;
  const auto check = [&](const Datagram& d) {
    EXPECT_EQ(d.bytes, std::vector<uint8_t>(1 + (i * 37) % 3000, uint8_t(i))) << i;
    EXPECT_EQ(d.FromString(), "127.0.0.1:" + std::to_string(sender.port()));
    EXPECT_GT(d.receive_time_ns, 0u);
    ++i;
  };
  EXPECT_EQ(receiver.Drain(1000, UdpSocket::kDrainMax, check), count);
  EXPECT_EQ(i, count);
}

TEST(SourceText, NamesEachAddressAndFollowsAChange) {
  SourceText text;
  sockaddr_in a{}, b{};
  a.sin_family = b.sin_family = AF_INET;
  inet_pton(AF_INET, "10.0.0.7", &a.sin_addr);
  a.sin_port = htons(30000);
  b = a;
  b.sin_port = htons(30001);
  EXPECT_EQ(text.Of(a), "10.0.0.7:30000");
  EXPECT_EQ(text.Of(a), "10.0.0.7:30000");
  EXPECT_EQ(text.Of(b), "10.0.0.7:30001");
  inet_pton(AF_INET, "10.0.0.8", &b.sin_addr);
  EXPECT_EQ(text.Of(b), "10.0.0.8:30001");
}

TEST(UdpSocket, ReceivesEachDatagramAtItsLengthWithSender) {
  UdpSocket receiver, sender;
  receiver.Bind(Loopback(0));
  sender.Bind(Loopback(0));
  ASSERT_NE(receiver.port(), 0);
  // A long datagram, then a short one: the second must not keep the first's tail.
  std::vector<uint8_t> big(9000), small = {1, 2, 3};
  for (size_t i = 0; i < big.size(); ++i) big[i] = static_cast<uint8_t>(i * 7);
  ASSERT_TRUE(sender.SendTo(Loopback(receiver.port()), big));
  ASSERT_TRUE(sender.SendTo(Loopback(receiver.port()), small));
  Datagram d;
  ASSERT_TRUE(receiver.Receive(&d, 1000));
  EXPECT_EQ(d.bytes, big);
  EXPECT_GT(d.receive_time_ns, 0u);
  EXPECT_EQ(d.FromString(), "127.0.0.1:" + std::to_string(sender.port()));
  ASSERT_TRUE(receiver.Receive(&d, 1000));
  EXPECT_EQ(d.bytes, small);
}

// The largest payload arrives whole; a larger one cannot be sent, so it never needs cutting.
TEST(UdpSocket, LargestDatagramArrivesWholeAndOversizedIsRefused) {
  UdpSocket receiver, sender;
  receiver.Bind(Loopback(0));
  sender.Bind(Loopback(0));
  const std::vector<uint8_t> largest(UdpSocket::kMaxDatagram, 0xAB);
  ASSERT_TRUE(sender.SendTo(Loopback(receiver.port()), largest));
  Datagram d;
  ASSERT_TRUE(receiver.Receive(&d, 1000));
  EXPECT_EQ(d.bytes, largest);
  EXPECT_FALSE(sender.SendTo(Loopback(receiver.port()), std::vector<uint8_t>(UdpSocket::kMaxDatagram + 1)));
  EXPECT_FALSE(receiver.Receive(&d, 20));
}

TEST(UdpSocket, TimeoutAndNonBlockingPollReturnFalse) {
  UdpSocket receiver;
  receiver.Bind(Loopback(0));
  Datagram d;
  d.bytes = {9};
  EXPECT_FALSE(receiver.Receive(&d, 0));
  EXPECT_FALSE(receiver.Receive(&d, 20));
  EXPECT_EQ(d.bytes, std::vector<uint8_t>{9});  // untouched when nothing arrived
}

TEST(UdpSocket, AddressesAreParsedAndBadOnesRefused) {
  EXPECT_EQ(ParseHostPort("*:9000").host, "");
  EXPECT_EQ(ParseHostPort("127.0.0.1:9000").port, 9000);
  EXPECT_THROW(ParseHostPort("127.0.0.1"), std::invalid_argument);
  EXPECT_THROW(ParseHostPort("127.0.0.1:70000"), std::invalid_argument);
  EXPECT_THROW(ParseHostPort(std::string("127.0.0.1:9000\0junk", 19)), std::invalid_argument);
  UdpSocket a, b;
  a.Bind(Loopback(0));
  EXPECT_THROW(b.Bind(Loopback(a.port())), std::runtime_error);  // port in use
}

}  // namespace
}  // namespace mocap

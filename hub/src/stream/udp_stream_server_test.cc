// The UDP stream on loopback: a subscriber gets every published frame with the parts it asked
// for, an unsubscribed or never-subscribed socket gets nothing, and bad requests are counted.
#include "stream/udp_stream_server.h"

#include <chrono>
#include <cstdio>
#include <thread>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "mocap_stream.pb.h"

namespace mocap::stream {
namespace {

SharedFrame Frame(uint64_t number, size_t points) {
  service::LiveFrame f;
  f.frame_number = number;
  f.cameras = 4;
  f.publish_ns = RealtimeNowNs();
  for (size_t i = 0; i < points; ++i) {
    service::LivePoint p;
    p.position = {static_cast<double>(i), 0.0, 0.0};
    p.marker = static_cast<int>(i);
    f.points.push_back(p);
  }
  return ShareFrame(f);
}

class Client {
 public:
  Client() { socket_.Bind({"127.0.0.1", 0}); }
  void Send(uint16_t port, const std::string& bytes) {
    socket_.SendTo({"127.0.0.1", port}, std::vector<uint8_t>(bytes.begin(), bytes.end()));
  }
  // The whole subscription: a first request, the hub's challenge, the request with its cookie.
  bool Subscribe(uint16_t port, uint32_t parts) {
    Send(port, EncodeSubscribe(parts));
    v1::StreamFrame challenge;
    if (!Receive(&challenge, 2000) || challenge.subscribe_cookie().empty()) return false;
    cookie_ = challenge.subscribe_cookie();
    Send(port, EncodeSubscribe(parts, cookie_));
    return true;
  }
  void Unsubscribe(uint16_t port) { Send(port, EncodeUnsubscribe(cookie_)); }
  // The next frame, or false within timeout_ms.
  bool Receive(v1::StreamFrame* frame, int timeout_ms) {
    Datagram d;
    if (!socket_.Receive(&d, timeout_ms)) return false;
    return frame->ParseFromArray(d.bytes.data(), static_cast<int>(d.bytes.size()));
  }
  uint16_t port() const { return socket_.port(); }

 private:
  UdpSocket socket_;
  std::string cookie_;
};

// Publishes frames until the server's stats show `subscribers` (requests are served between
// frames), bounded.
bool WaitForSubscribers(UdpStreamServer& server, size_t subscribers) {
  for (int i = 0; i < 200; ++i) {
    if (server.stats().subscribers == subscribers) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  return false;
}

UdpStreamOptions Loopback() {
  UdpStreamOptions o;
  o.listen = "127.0.0.1:0";
  return o;
}

class UdpStreamServerPaths : public ::testing::TestWithParam<size_t> {};

// Sent inline by the publisher (few subscribers) and by the sending thread (inline_subscribers 0).
INSTANTIATE_TEST_SUITE_P(InlineAndThread, UdpStreamServerPaths, ::testing::Values(size_t{8}, size_t{0}));

TEST_P(UdpStreamServerPaths, SubscribersGetTheirPartsOfEveryFrame) {
  UdpStreamOptions options = Loopback();
  options.inline_subscribers = GetParam();
  UdpStreamServer server(options);
  Client points, bodies, stranger;
  ASSERT_TRUE(points.Subscribe(server.port(), kPartPoints));
  ASSERT_TRUE(bodies.Subscribe(server.port(), kPartBodies));
  ASSERT_TRUE(WaitForSubscribers(server, 2));
  for (uint64_t n = 1; n <= 3; ++n) {
    server.Publish(Frame(n, 5));
    v1::StreamFrame a, b;
    ASSERT_TRUE(points.Receive(&a, 2000));
    ASSERT_TRUE(bodies.Receive(&b, 2000));
    EXPECT_EQ(a.frame_number(), n);
    EXPECT_EQ(a.points_size(), 5);
    EXPECT_EQ(a.points(4).marker(), 5);
    EXPECT_EQ(b.frame_number(), n);
    EXPECT_EQ(b.points_size(), 0);
    EXPECT_EQ(b.parts(), kPartBodies);
  }
  v1::StreamFrame none;
  EXPECT_FALSE(stranger.Receive(&none, 50));
  EXPECT_EQ(server.stats().datagrams, 6u);

  points.Send(server.port(), EncodeUnsubscribe());  // without the cookie: refused
  points.Unsubscribe(server.port());
  ASSERT_TRUE(WaitForSubscribers(server, 1));
  server.Publish(Frame(4, 5));
  v1::StreamFrame b;
  ASSERT_TRUE(bodies.Receive(&b, 2000));
  EXPECT_EQ(b.frame_number(), 4u);
  EXPECT_FALSE(points.Receive(&none, 50));
  // Every frame that went out is in the stream's own latency figure.
  EXPECT_EQ(server.StatsJson()["publish_to_sent_ms"]["frames"], 4u);
}

TEST(UdpStreamServer, BadRequestsAreCountedAndChangeNothing) {
  UdpStreamServer server(Loopback());
  Client client;
  client.Send(server.port(), "garbage that is no request");
  client.Send(server.port(), EncodeSubscribe(128));
  for (int i = 0; i < 200 && server.stats().bad_requests < 2; ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  EXPECT_EQ(server.stats().bad_requests, 2u);
  EXPECT_EQ(server.stats().subscribers, 0u);
}

TEST(UdpStreamServer, SubscriptionsRunOutUnlessRenewed) {
  UdpStreamOptions o = Loopback();
  o.subscription_s = 0.2;
  UdpStreamServer server(o);
  Client client;
  ASSERT_TRUE(client.Subscribe(server.port(), kPartPoints));
  ASSERT_TRUE(WaitForSubscribers(server, 1));
  EXPECT_TRUE(WaitForSubscribers(server, 0));
}

// The probe: one small forged StreamRequest made serve send 169 836 bytes to the victim in 8 s.
// Now an address gets frames only after echoing its cookie; an unproven one gets at most a
// challenge no larger than its request, and a source over its rate gets nothing.
TEST(UdpStreamServer, UnprovenAddressesGetNoFramesAndNoAmplification) {
  UdpStreamServer server(Loopback());
  Client client;
  const std::string first = EncodeSubscribe(kPartPoints);
  client.Send(server.port(), first);
  v1::StreamFrame challenge;
  ASSERT_TRUE(client.Receive(&challenge, 2000));
  EXPECT_EQ(challenge.frame_number(), 0u);
  EXPECT_EQ(challenge.points_size(), 0);
  EXPECT_LE(challenge.ByteSizeLong(), first.size());
  EXPECT_EQ(server.stats().subscribers, 0u);
  // A wrong cookie (answered with a new challenge, no larger than it) and an unpadded first
  // request (not answered at all): no subscription.
  const std::string wrong = EncodeSubscribe(kPartPoints, std::string(16, 'x'));
  client.Send(server.port(), wrong);
  v1::StreamRequest bare;
  bare.set_version(1);
  bare.mutable_subscribe()->set_parts(kPartPoints);
  client.Send(server.port(), bare.SerializeAsString());
  for (int i = 0; i < 5; ++i) server.Publish(Frame(static_cast<uint64_t>(i + 1), 3));
  v1::StreamFrame got;
  ASSERT_TRUE(client.Receive(&got, 2000));
  EXPECT_FALSE(got.subscribe_cookie().empty());
  EXPECT_LE(got.ByteSizeLong(), wrong.size());
  EXPECT_FALSE(client.Receive(&got, 100)) << got.DebugString();
  EXPECT_EQ(server.stats().subscribers, 0u);
  EXPECT_EQ(server.stats().challenges, 2u);  // the first request and the wrong cookie
  // A flood from one source: past the burst, requests are dropped unanswered.
  for (int i = 0; i < 200; ++i) client.Send(server.port(), first);
  for (int i = 0; i < 200 && server.stats().unproven < 203; ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  size_t answers = 0;
  while (client.Receive(&got, 50)) ++answers;
  std::printf("200 unproven subscriptions from one source: %zu challenges answered, %llu dropped over the rate\n",
              answers, static_cast<unsigned long long>(server.stats().rate_limited));
  EXPECT_GT(server.stats().rate_limited, 100u);
  EXPECT_LE(answers, 70u);
}

TEST(UdpStreamServer, OptionsChecked) {
  UdpStreamOptions o = Loopback();
  o.multicast = "10.0.0.1:7803";
  EXPECT_THROW(UdpStreamServer{o}, std::invalid_argument);
  o.multicast = "239.255.42.1:0";
  EXPECT_THROW(UdpStreamServer{o}, std::invalid_argument);
  o = Loopback();
  o.queue_frames = 0;
  EXPECT_THROW(UdpStreamServer{o}, std::invalid_argument);
  o = Loopback();
  o.listen = "127.0.0.1:99999";
  EXPECT_THROW(UdpStreamServer{o}, std::invalid_argument);
}

}  // namespace
}  // namespace mocap::stream

// The UDP stream on loopback: a subscriber gets every published frame with the parts it asked
// for, an unsubscribed or never-subscribed socket gets nothing, and bad requests are counted.
#include "stream/udp_stream_server.h"

#include <chrono>
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
  // The next frame, or false within timeout_ms.
  bool Receive(v1::StreamFrame* frame, int timeout_ms) {
    Datagram d;
    if (!socket_.Receive(&d, timeout_ms)) return false;
    return frame->ParseFromArray(d.bytes.data(), static_cast<int>(d.bytes.size()));
  }

 private:
  UdpSocket socket_;
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
  points.Send(server.port(), EncodeSubscribe(kPartPoints));
  bodies.Send(server.port(), EncodeSubscribe(kPartBodies));
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

  points.Send(server.port(), EncodeUnsubscribe());
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
  client.Send(server.port(), EncodeSubscribe(kPartPoints));
  ASSERT_TRUE(WaitForSubscribers(server, 1));
  EXPECT_TRUE(WaitForSubscribers(server, 0));
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

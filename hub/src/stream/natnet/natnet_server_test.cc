// The NatNet server's socket on loopback: a unicast client connects, gets NAT_SERVERINFO and
// then every published frame at the address it sent from, asks for the model definitions and
// the newest frame, is refused a command and answered unrecognized for garbage; it stops getting
// frames once it disconnects; a client over max_clients is told so and gets no frames; frames
// reach a client complete and in order whether the hub's loop sends them as they are published
// or the server's thread does (requests in between, or more clients than inline_clients).
#include <arpa/inet.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstring>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "stream/natnet/natnet_server.h"
#include "stream/shared_frame.h"

namespace mocap::stream::natnet {
namespace {

class Client {
 public:
  explicit Client(uint16_t port) {
    fd_ = socket(AF_INET, SOCK_DGRAM, 0);
    timeval tv{0, 300'000};
    setsockopt(fd_, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
    server_.sin_family = AF_INET;
    server_.sin_port = htons(port);
    server_.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  }
  ~Client() { close(fd_); }
  void Send(uint16_t id, const std::string& payload = "") {
    std::string p = {static_cast<char>(id), static_cast<char>(id >> 8), static_cast<char>(payload.size() & 0xff),
                     static_cast<char>(payload.size() >> 8)};
    p += payload;
    sendto(fd_, p.data(), p.size(), 0, reinterpret_cast<const sockaddr*>(&server_), sizeof server_);
  }
  void SendRaw(const std::string& p) {
    sendto(fd_, p.data(), p.size(), 0, reinterpret_cast<const sockaddr*>(&server_), sizeof server_);
  }
  // The next datagram of this message id (others skipped); empty after a quiet 300 ms.
  std::string Next(uint16_t id) {
    char buf[70000];
    for (int i = 0; i < 200; ++i) {
      const ssize_t n = recv(fd_, buf, sizeof buf, 0);
      if (n < 4) return "";
      if ((static_cast<uint8_t>(buf[0]) | static_cast<uint8_t>(buf[1]) << 8) == id) return std::string(buf, static_cast<size_t>(n));
    }
    return "";
  }

 private:
  int fd_ = -1;
  sockaddr_in server_{};
};

SharedFrame Frame(uint64_t number) {
  auto f = std::make_shared<pipeline::LiveFrame>();
  f->frame_number = number;
  f->publish_ns = RealtimeNowNs();
  pipeline::LiveBody b;
  b.id = 1;
  b.name = "drone";
  b.tracked = true;
  f->bodies = {b};
  return f;
}

int32_t FrameNumber(const std::string& p) {
  int32_t n = -1;
  std::memcpy(&n, p.data() + 4, 4);
  return n;
}

NatNetOptions Unicast(size_t max_clients = 8) {
  NatNetOptions o;
  o.listen = "127.0.0.1:0";
  o.multicast = "";
  o.max_clients = max_clients;
  return o;
}

Model OneBody() {
  Model m;
  m.rate_hz = 100;
  RigidBodyDefinition d;
  d.name = "drone";
  d.markers = {{0, 0, 0}, {50, 0, 0}, {0, 50, 0}};
  m.bodies = {d};
  return m;
}

TEST(NatNetServer, UnicastClientGetsAnswersAndFrames) {
  NatNetServer server(Unicast(), OneBody());
  Client c(server.port());
  c.Send(kConnect);
  const std::string info = c.Next(kServerInfo);
  ASSERT_EQ(info.size(), 283u);
  EXPECT_EQ(info[4 + 274], 0);  // not multicast
  c.Send(kRequestModelDef);
  EXPECT_EQ(c.Next(kModelDef), EncodeModelDef(OneBody(), Version{}));
  for (uint64_t n = 1; n <= 3; ++n) {
    server.Publish(Frame(n));
    EXPECT_EQ(FrameNumber(c.Next(kFrameOfData)), static_cast<int32_t>(n));
  }
  c.Send(kRequestFrameOfData);
  EXPECT_EQ(FrameNumber(c.Next(kFrameOfData)), 3);
  c.Send(kRequest, std::string("StartRecording") + '\0');
  const std::string refused = c.Next(kResponse);
  ASSERT_EQ(refused.size(), 8u);
  EXPECT_EQ(refused[4], 1);
  c.SendRaw("\x07");
  EXPECT_EQ(c.Next(kUnrecognizedRequest).size(), 4u);
  c.Send(kDisconnect);
  std::this_thread::sleep_for(std::chrono::milliseconds(50));
  server.Publish(Frame(4));
  EXPECT_EQ(c.Next(kFrameOfData), "");
  for (int i = 0; i < 100 && server.stats().clients != 0; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  const NatNetStats s = server.stats();
  EXPECT_EQ(s.frames, 3u);
  EXPECT_EQ(s.refused, 2u);
  EXPECT_EQ(s.clients, 0u);
  EXPECT_EQ(server.StatsJson()["publish_to_sent_ms"]["frames"], 3u);
}

TEST(NatNetServer, ClientsOverTheLimitAreToldAndGetNoFrames) {
  NatNetServer server(Unicast(1), OneBody());
  Client first(server.port()), second(server.port());
  first.Send(kConnect);
  ASSERT_FALSE(first.Next(kServerInfo).empty());
  second.Send(kConnect);
  const std::string told = second.Next(kMessageString);
  EXPECT_NE(told.find("1 unicast clients already"), std::string::npos) << told;
  server.Publish(Frame(9));
  EXPECT_EQ(FrameNumber(first.Next(kFrameOfData)), 9);
  EXPECT_EQ(second.Next(kFrameOfData), "");
}

// Publishes frames 1..n to one unicast client, a keep-alive every third frame (the server's thread
// takes the sockets to answer it, so frames published meanwhile queue); the frame numbers received.
std::vector<int32_t> PublishWithRequestsBetween(NatNetServer* server, Client* client, int n) {
  std::vector<int32_t> got;
  for (int i = 1; i <= n; ++i) {
    server->Publish(Frame(static_cast<uint64_t>(i)));
    if (i % 3 == 0) client->Send(kKeepAlive);
  }
  for (std::string p = client->Next(kFrameOfData); !p.empty(); p = client->Next(kFrameOfData)) {
    got.push_back(FrameNumber(p));
    if (got.size() == static_cast<size_t>(n)) break;
  }
  return got;
}

TEST(NatNetServer, FramesArriveCompleteAndInOrderOnEitherPath) {
  for (size_t inline_clients : {size_t{8}, size_t{0}}) {
    NatNetOptions options = Unicast();
    options.inline_clients = inline_clients;
    options.queue_frames = 256;
    NatNetServer server(options, OneBody());
    Client c(server.port());
    c.Send(kConnect);
    ASSERT_FALSE(c.Next(kServerInfo).empty());
    const std::vector<int32_t> got = PublishWithRequestsBetween(&server, &c, 150);
    std::vector<int32_t> want(150);
    for (int i = 0; i < 150; ++i) want[static_cast<size_t>(i)] = i + 1;
    EXPECT_EQ(got, want) << "inline_clients " << inline_clients;
    const NatNetStats s = server.stats();
    EXPECT_EQ(s.frames, 150u);
    if (inline_clients == 0) {
      EXPECT_EQ(s.frames_on_publish, 0u);
    }
    std::printf("inline_clients %zu: %llu of %llu frames sent on publish\n", inline_clients,
                static_cast<unsigned long long>(s.frames_on_publish), static_cast<unsigned long long>(s.frames));
  }
}

TEST(NatNetServer, OptionsAreChecked) {
  NatNetOptions o = Unicast();
  o.multicast = "10.0.0.1";
  EXPECT_THROW(o.Check(), std::invalid_argument);
  o = Unicast();
  o.version = "2.9";
  EXPECT_THROW(o.Check(), std::invalid_argument);
  o = Unicast();
  o.client_timeout_s = 0;
  EXPECT_THROW(o.Check(), std::invalid_argument);
}

}  // namespace
}  // namespace mocap::stream::natnet

// The RT server over real loopback sockets: greeting, parameters and a TCP stream; a client that
// never reads loses frames for itself only while another gets every one; 100 clients at once;
// the client limit; clients vanishing mid-stream; the shutdown event.
#include "stream/qtm/qtm_rt_server.h"

#include <arpa/inet.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <thread>

#include <gtest/gtest.h>

#include "stream/qtm/rt_test_util.h"

namespace mocap::stream::qtm {
namespace {

using namespace std::chrono_literals;

// A blocking client with a bounded read timeout.
class TestClient {
 public:
  explicit TestClient(uint16_t port) {
    fd_ = socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_port = htons(port);
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    connected_ = connect(fd_, reinterpret_cast<sockaddr*>(&a), sizeof a) == 0;
  }
  ~TestClient() { Close(); }
  void Close() {
    if (fd_ >= 0) close(fd_);
    fd_ = -1;
  }
  bool connected() const { return connected_; }
  int fd() const { return fd_; }
  void Send(const std::string& command) {
    const std::string p = MakeStringPacket(PacketType::kCommand, command);
    ASSERT_EQ(send(fd_, p.data(), p.size(), MSG_NOSIGNAL), static_cast<ssize_t>(p.size()));
  }
  // The next packet, or type 99 after `timeout` / on EOF (eof() tells which). The default bounds
  // a wait for what must come: reached only when something is stuck (no timing is asserted).
  testing::Packet Next(std::chrono::milliseconds timeout = 30000ms) {
    const auto end = std::chrono::steady_clock::now() + timeout;
    while (true) {
      std::vector<testing::Packet> got = testing::SplitPackets(&buffer_);
      pending_.insert(pending_.end(), got.begin(), got.end());
      if (!pending_.empty()) {
        testing::Packet p = pending_.front();
        pending_.erase(pending_.begin());
        return p;
      }
      const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(end - std::chrono::steady_clock::now());
      if (left.count() <= 0 || eof_) return {99, ""};
      pollfd p{fd_, POLLIN, 0};
      if (poll(&p, 1, static_cast<int>(left.count())) <= 0) continue;
      char chunk[65536];
      const ssize_t n = recv(fd_, chunk, sizeof chunk, 0);
      if (n <= 0) eof_ = true;
      else buffer_.append(chunk, static_cast<size_t>(n));
    }
  }
  bool eof() const { return eof_; }

 private:
  int fd_ = -1;
  bool connected_ = false;
  bool eof_ = false;
  std::string buffer_;
  std::vector<testing::Packet> pending_;
};

RtSystem TwoCameras() {
  RtSystem s;
  s.rate_hz = 200;
  for (uint32_t id : {3u, 5u}) {
    Camera c;
    c.id = id;
    s.rig.cameras.push_back(c);
  }
  return s;
}

SharedFrame MakeFrame(uint64_t number, int points) {
  auto f = std::make_shared<pipeline::LiveFrame>();
  f->frame_number = number;
  f->cameras = 2;
  for (int i = 0; i < points; ++i) {
    pipeline::LivePoint p;
    p.position = {double(i), 1, 2};
    p.marker = i;
    p.id = static_cast<uint64_t>(i) + 1;
    f->points.push_back(p);
  }
  return f;
}

QtmRtOptions Loopback() {
  QtmRtOptions o;
  o.listen = "127.0.0.1:0";
  return o;
}

TEST(QtmRtServer, GreetingParametersAndATcpStream) {
  QtmRtServer server(Loopback(), TwoCameras());
  ASSERT_NE(server.port(), 0);
  TestClient c(server.port());
  ASSERT_TRUE(c.connected());
  EXPECT_EQ(c.Next().Text(), "QTM RT Interface connected");
  c.Send("Version 1.25");
  EXPECT_EQ(c.Next().Text(), "Version set to 1.25");
  c.Send("GetParameters General");
  const testing::Packet xml = c.Next();
  EXPECT_EQ(xml.type, 2u);
  EXPECT_NE(xml.Text().find("<Frequency>200</Frequency>"), std::string::npos);
  EXPECT_NE(xml.Text().find("<ID>5</ID>"), std::string::npos);
  c.Send("StreamFrames AllFrames 3D");
  EXPECT_EQ(c.Next().type, 4u);  // no frames yet
  for (uint64_t i = 1; i <= 3; ++i) server.Publish(MakeFrame(i, 4));
  testing::Packet p = c.Next();
  EXPECT_EQ(p.type, 6u);  // Connected: frames flow
  for (uint64_t i = 1; i <= 3; ++i) {
    p = c.Next();
    ASSERT_EQ(p.type, 3u);
    const testing::Frame f = testing::ReadFrame(p.body);
    EXPECT_EQ(f.frame_number, i);
    EXPECT_EQ(f.components.at(0).count, 4u);
  }
  c.Send("Bogus");
  EXPECT_EQ(c.Next().type, 0u);
  c.Send("StreamFrames Stop");
  c.Send("ByteOrder");
  EXPECT_EQ(c.Next().Text(), "Byte order is little endian");
  EXPECT_EQ(server.stats().errors, 1u);
}

TEST(QtmRtServer, ASilentClientLosesFramesForItselfOnly) {
  QtmRtServer server(Loopback(), TwoCameras());
  TestClient silent(server.port());
  TestClient reader(server.port());
  const int small = 4096;
  setsockopt(silent.fd(), SOL_SOCKET, SO_RCVBUF, &small, sizeof small);
  silent.Send("StreamFrames AllFrames 3D");
  reader.Send("StreamFrames AllFrames 3D");
  EXPECT_EQ(reader.Next().type, 1u);  // greeting
  EXPECT_EQ(reader.Next().type, 4u);
  // 24 kB frames: 300 of them are far more than the kernel buffers plus the client's bound.
  const int frames = 300;
  int received = 0;
  for (int i = 0; i < frames; ++i) {
    server.Publish(MakeFrame(static_cast<uint64_t>(i), 2000));
    // Paced by the reader, so the hand-over queue never drops: every loss is the silent one's.
    while (true) {
      const testing::Packet p = reader.Next();
      ASSERT_NE(p.type, 99u) << "reader starved at frame " << i;
      if (p.type == 3u) {
        EXPECT_EQ(testing::ReadFrame(p.body).frame_number, static_cast<uint32_t>(i));
        ++received;
        break;
      }
    }
  }
  EXPECT_EQ(received, frames);
  const QtmRtStats s = server.stats();
  EXPECT_GT(s.frames_dropped, 0u);
  EXPECT_EQ(s.queue_dropped, 0u);
  EXPECT_EQ(s.clients, 2u);  // dropping frames is not a reason to close
}

TEST(QtmRtServer, AHundredClientsAtOnceAndTheLimit) {
  QtmRtOptions o = Loopback();
  o.max_clients = 100;
  QtmRtServer server(o, TwoCameras());
  std::vector<std::unique_ptr<TestClient>> clients;
  for (int i = 0; i < 100; ++i) clients.push_back(std::make_unique<TestClient>(server.port()));
  for (auto& c : clients) {
    ASSERT_TRUE(c->connected());
    EXPECT_EQ(c->Next().Text(), "QTM RT Interface connected");
  }
  TestClient extra(server.port());
  const testing::Packet refusal = extra.Next();
  EXPECT_EQ(refusal.type, 0u);
  EXPECT_EQ(refusal.Text(), "Connection refused. Max number of clients reached.");
  EXPECT_EQ(extra.Next(2000ms).type, 99u);
  EXPECT_TRUE(extra.eof());
  EXPECT_EQ(server.stats().refused, 1u);
}

TEST(QtmRtServer, ClientsVanishingMidStreamAndTheShutdownEvent) {
  auto server = std::make_unique<QtmRtServer>(Loopback(), TwoCameras());
  for (int round = 0; round < 5; ++round) {
    TestClient gone(server->port());
    gone.Send("StreamFrames AllFrames 3D");
    for (int i = 0; i < 20; ++i) server->Publish(MakeFrame(static_cast<uint64_t>(i), 2000));
    // Closing with unread data resets the connection while the server writes.
  }
  TestClient last(server->port());
  EXPECT_EQ(last.Next().type, 1u);
  last.Send("GetCurrentFrame 3DNoLabels");
  testing::Packet p = last.Next();
  while (p.type == 6u) p = last.Next();
  ASSERT_EQ(p.type, 3u);
  EXPECT_EQ(testing::ReadFrame(p.body).components.at(0).type, 2u);
  // (Bounded at 30 s, reached only when the count is stuck.)
  for (int i = 0; i < 1500 && server->stats().clients != 1; ++i) std::this_thread::sleep_for(20ms);
  EXPECT_EQ(server->stats().clients, 1u);
  server.reset();
  p = last.Next();
  EXPECT_EQ(p.type, 6u);
  EXPECT_EQ(p.body, std::string(1, 12));  // QTM Shutting Down
  EXPECT_EQ(last.Next(2000ms).type, 99u);
  EXPECT_TRUE(last.eof());
}

TEST(QtmRtServer, CaptureEventsFollowTheHubsEvents) {
  QtmRtServer server(Loopback(), TwoCameras());
  TestClient c(server.port());
  EXPECT_EQ(c.Next().type, 1u);
  server.OnCapture({pipeline::CaptureEvent::Kind::kStopped, "before"});  // idle already: nothing to tell
  server.OnCapture({pipeline::CaptureEvent::Kind::kStarted, "walk"});
  EXPECT_EQ(c.Next().body, std::string(1, 3));  // Capture Started
  c.Send("GetState");
  EXPECT_EQ(c.Next().body, std::string(1, 3));
  server.OnCapture({pipeline::CaptureEvent::Kind::kStopped, "walk"});
  EXPECT_EQ(c.Next().body, std::string(1, 4));  // Capture Stopped
  c.Send("GetState");
  EXPECT_EQ(c.Next().body, std::string(1, 2));  // and no frames: Connection Closed
}

TEST(QtmRtServer, BadOptionsAndBusyPorts) {
  QtmRtOptions o = Loopback();
  o.listen = "nonsense";
  EXPECT_THROW(QtmRtServer(o, TwoCameras()), std::invalid_argument);
  QtmRtServer first(Loopback(), TwoCameras());
  o.listen = "127.0.0.1:" + std::to_string(first.port());
  EXPECT_THROW(QtmRtServer(o, TwoCameras()), std::runtime_error);
}

}  // namespace
}  // namespace mocap::stream::qtm

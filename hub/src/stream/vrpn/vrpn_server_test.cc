// The VRPN server's sockets on loopback: a client connecting by TCP and one reached through the
// UDP lookup (the server connects back) both exchange cookies, get the trackers described and a
// fitted body's report stamped with the trigger time; a lookup naming another host is refused;
// an unfitted body sends nothing; fifty trackers are described and reported; --vrpn-velocity's
// report is the last two fitted poses' difference over their time; reports arrive complete and in
// order whether the hub's loop sends them as frames are published or the server's thread does.
#include <arpa/inet.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "ingest/udp_socket.h"
#include "stream/shared_frame.h"
#include "stream/vrpn/vrpn_server.h"

namespace mocap::stream::vrpn {
namespace {

// Waits for what must come end by this bound only when something is stuck: no timing is asserted.
constexpr std::chrono::seconds kStuck{30};

// Polls until `done` holds or kStuck passed.
template <typename Done>
void WaitUntil(Done done) {
  const auto end = std::chrono::steady_clock::now() + kStuck;
  while (!done() && std::chrono::steady_clock::now() < end) std::this_thread::sleep_for(std::chrono::milliseconds(10));
}

// Reads messages from a connected socket until `want` of type `type` arrived (or kStuck passed).
std::vector<ReceivedMessage> ReadUntil(int fd, int32_t type, size_t want) {
  timeval tv{0, 200'000};
  setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
  std::string cookie;
  MessageReader reader;
  std::vector<ReceivedMessage> got;
  size_t matching = 0;
  const auto end = std::chrono::steady_clock::now() + kStuck;
  while (matching < want && std::chrono::steady_clock::now() < end) {
    uint8_t buf[4096];
    const ssize_t n = recv(fd, buf, sizeof buf, 0);
    if (n <= 0) continue;
    size_t at = 0;
    if (cookie.size() < kCookieSize) {
      at = std::min(kCookieSize - cookie.size(), static_cast<size_t>(n));
      cookie.append(reinterpret_cast<char*>(buf), at);
    }
    reader.Feed(buf + at, static_cast<size_t>(n) - at);
    ReceivedMessage m;
    while (reader.Next(&m)) {
      matching += m.type == type;
      got.push_back(m);
    }
  }
  EXPECT_EQ(CheckCookie(reinterpret_cast<const uint8_t*>(cookie.data())), "");
  return got;
}

// A tcp:// client that sent its cookie and that the server counted as connected; -1 on failure.
int ConnectedTcpClient(const VrpnServer& server) {
  const int tcp = socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in to{};
  to.sin_family = AF_INET;
  to.sin_port = htons(server.port());
  to.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  if (connect(tcp, reinterpret_cast<sockaddr*>(&to), sizeof to) != 0 ||
      send(tcp, Cookie().data(), kCookieSize, 0) != static_cast<ssize_t>(kCookieSize)) {
    close(tcp);
    return -1;
  }
  WaitUntil([&] { return server.stats().connections >= 1; });
  return tcp;
}

SharedFrame Frame(bool tracked) {
  auto f = std::make_shared<pipeline::LiveFrame>();
  f->frame_number = 5;
  f->trigger_time_ns = 1'700'000'000'250'000'000ull;
  f->publish_ns = RealtimeNowNs();
  pipeline::LiveBody b;
  b.id = 2;
  b.name = "wand";
  b.tracked = tracked;
  b.position = {1000, 2000, 3000};
  f->bodies = {pipeline::LiveBody{}, b};
  f->bodies[0].id = 1;
  return f;
}

void ExpectWandReport(const std::vector<ReceivedMessage>& got) {
  ASSERT_FALSE(got.empty());
  EXPECT_EQ(got[0].type, kSenderDescription);
  const ReceivedMessage& report = got.back();
  EXPECT_EQ(report.type, kPosQuat);
  EXPECT_EQ(report.sender, 1);
  EXPECT_EQ(report.time.seconds, 1'700'000'000u);
  EXPECT_EQ(report.time.microseconds, 250'000u);
  ASSERT_EQ(report.payload.size(), 64u);
}

TEST(VrpnServer, TcpAndLookupClientsGetReports) {
  VrpnOptions o;
  o.listen = "127.0.0.1:0";
  VrpnServer server(o, {"drone", "wand"});
  // A tcp:// client.
  const int tcp = socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in to{};
  to.sin_family = AF_INET;
  to.sin_port = htons(server.port());
  to.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  ASSERT_EQ(connect(tcp, reinterpret_cast<sockaddr*>(&to), sizeof to), 0);
  ASSERT_EQ(send(tcp, Cookie().data(), kCookieSize, 0), static_cast<ssize_t>(kCookieSize));
  // A client that asks to be called back on its own listening port.
  const int listener = socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in mine{};
  mine.sin_family = AF_INET;
  mine.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  ASSERT_EQ(bind(listener, reinterpret_cast<sockaddr*>(&mine), sizeof mine), 0);
  listen(listener, 1);
  socklen_t len = sizeof mine;
  getsockname(listener, reinterpret_cast<sockaddr*>(&mine), &len);
  const int udp = socket(AF_INET, SOCK_DGRAM, 0);
  const std::string other = "10.1.2.3 " + std::to_string(ntohs(mine.sin_port));
  sendto(udp, other.c_str(), other.size() + 1, 0, reinterpret_cast<sockaddr*>(&to), sizeof to);
  const std::string lookup = "127.0.0.1 " + std::to_string(ntohs(mine.sin_port));
  sendto(udp, lookup.c_str(), lookup.size() + 1, 0, reinterpret_cast<sockaddr*>(&to), sizeof to);
  const int called = accept(listener, nullptr, nullptr);
  ASSERT_GE(called, 0);
  ASSERT_EQ(send(called, Cookie().data(), kCookieSize, 0), static_cast<ssize_t>(kCookieSize));
  // Both connected: the descriptions come first, then a fitted body's report.
  WaitUntil([&] { return server.stats().connections >= 2; });
  ASSERT_EQ(server.stats().connections, 2u);
  server.Publish(Frame(false));
  server.Publish(Frame(true));
  ExpectWandReport(ReadUntil(tcp, kPosQuat, 1));
  ExpectWandReport(ReadUntil(called, kPosQuat, 1));
  // The figures are counted just after the bytes leave.
  WaitUntil([&] { return server.stats().reports >= 2; });
  const VrpnStats s = server.stats();
  EXPECT_EQ(s.lookups, 1u);
  EXPECT_EQ(s.refused, 1u);  // the lookup naming 10.1.2.3
  EXPECT_EQ(s.reports, 2u);  // one fitted frame to two clients
  for (int fd : {tcp, listener, udp, called}) close(fd);
}

double BeF64At(const std::string& s, size_t at) {
  uint64_t bits = 0;
  for (int i = 0; i < 8; ++i) bits = bits << 8 | static_cast<uint8_t>(s[at + i]);
  double v;
  std::memcpy(&v, &bits, 8);
  return v;
}

TEST(VrpnServer, VelocityFromTheLastTwoFittedPoses) {
  VrpnOptions o;
  o.listen = "127.0.0.1:0";
  o.velocity = true;
  VrpnServer server(o, {"drone"});
  const int tcp = ConnectedTcpClient(server);
  ASSERT_GE(tcp, 0);
  for (int n = 0; n < 2; ++n) {
    auto f = std::make_shared<pipeline::LiveFrame>();
    f->trigger_time_ns = 1'000'000'000ull + static_cast<uint64_t>(n) * 10'000'000ull;  // 10 ms apart
    pipeline::LiveBody b;
    b.id = 1;
    b.tracked = true;
    b.position = {100.0 + 5.0 * n, 0, 0};  // 5 mm in 10 ms: 0.5 m/s
    b.orientation = Eigen::Quaterniond(Eigen::AngleAxisd(0.01 * n, Eigen::Vector3d::UnitZ()));
    f->bodies = {b};
    server.Publish(f);
  }
  const std::vector<ReceivedMessage> got = ReadUntil(tcp, kVelocity, 1);
  const ReceivedMessage* velocity = nullptr;
  for (const ReceivedMessage& m : got)
    if (m.type == kVelocity) velocity = &m;
  ASSERT_NE(velocity, nullptr);
  ASSERT_EQ(velocity->payload.size(), 72u);
  EXPECT_NEAR(BeF64At(velocity->payload, 8), 0.5, 1e-9);
  EXPECT_NEAR(BeF64At(velocity->payload, 16), 0.0, 1e-12);
  EXPECT_NEAR(BeF64At(velocity->payload, 64), 0.01, 1e-12);  // vel_quat_dt
  EXPECT_NEAR(2 * std::asin(BeF64At(velocity->payload, 48)), 0.01, 1e-9);  // the rotation over dt: 0.01 rad about z
  close(tcp);
}

TEST(VrpnServer, FiftyTrackers) {
  VrpnOptions o;
  o.listen = "127.0.0.1:0";
  std::vector<std::string> names;
  auto f = std::make_shared<pipeline::LiveFrame>();
  f->trigger_time_ns = 1'000'000'000;
  for (uint32_t i = 1; i <= 50; ++i) {
    names.push_back("body" + std::to_string(i));
    pipeline::LiveBody b;
    b.id = i;
    b.tracked = true;
    b.position = {1000.0 * i, 0, 0};
    f->bodies.push_back(b);
  }
  VrpnServer server(o, names);
  const int tcp = ConnectedTcpClient(server);
  ASSERT_GE(tcp, 0);
  server.Publish(f);
  const std::vector<ReceivedMessage> got = ReadUntil(tcp, kPosQuat, 50);
  std::vector<std::string> described;
  std::vector<int32_t> reported;
  for (const ReceivedMessage& m : got) {
    if (m.type == kSenderDescription) described.push_back(m.payload.substr(4, m.payload.find('\0', 4) - 4));
    if (m.type == kPosQuat) reported.push_back(m.sender);
  }
  EXPECT_EQ(described, names);
  ASSERT_EQ(reported.size(), 50u);
  for (int32_t i = 0; i < 50; ++i) EXPECT_EQ(reported[static_cast<size_t>(i)], i);
  close(tcp);
}

TEST(VrpnServer, ReportsArriveCompleteAndInOrderOnEitherPath) {
  for (size_t inline_clients : {size_t{8}, size_t{0}}) {
    VrpnOptions o;
    o.listen = "127.0.0.1:0";
    o.inline_clients = inline_clients;
    o.queue_frames = 256;
    VrpnServer server(o, {"drone"});
    const int tcp = ConnectedTcpClient(server);
    ASSERT_GE(tcp, 0);
    constexpr int kFrames = 150;
    for (int n = 0; n < kFrames; ++n) {
      auto f = std::make_shared<pipeline::LiveFrame>();
      f->frame_number = static_cast<uint64_t>(n);
      f->trigger_time_ns = 1'000'000'000ull + static_cast<uint64_t>(n) * 1'000'000ull;  // 1 ms apart
      f->publish_ns = RealtimeNowNs();
      pipeline::LiveBody b;
      b.id = 1;
      b.tracked = true;
      f->bodies = {b};
      server.Publish(f);
    }
    std::vector<uint32_t> microseconds;
    for (const ReceivedMessage& m : ReadUntil(tcp, kPosQuat, kFrames))
      if (m.type == kPosQuat) microseconds.push_back(m.time.microseconds);
    ASSERT_EQ(microseconds.size(), static_cast<size_t>(kFrames)) << "inline_clients " << inline_clients;
    for (int n = 0; n < kFrames; ++n) EXPECT_EQ(microseconds[static_cast<size_t>(n)], static_cast<uint32_t>(n) * 1000u);
    const VrpnStats s = server.stats();
    EXPECT_EQ(s.frames, static_cast<uint64_t>(kFrames));
    if (inline_clients == 0) {
      EXPECT_EQ(s.frames_on_publish, 0u);
    }
    std::printf("inline_clients %zu: %llu of %llu frames sent on publish\n", inline_clients,
                static_cast<unsigned long long>(s.frames_on_publish), static_cast<unsigned long long>(s.frames));
    close(tcp);
  }
}

}  // namespace
}  // namespace mocap::stream::vrpn

// VRPN without sockets: the cookie both ways (a minor version differs and is accepted, another
// major or a bad log mode is refused), messages marshalled as vrpn_Connection lays them out
// (big-endian header, 8-byte padding), a byte stream cut anywhere into messages, the session's
// descriptions once the cookie checks out, a pong for a client tracker's ping, and refusals of
// what no VRPN client sends (the real client, libmotioncapture's VRPN, reads the server in
// tests/stream/natnet_vrpn_vmc_test.py).
#include <arpa/inet.h>

#include <cstring>
#include <string>

#include <gtest/gtest.h>

#include "stream/vrpn/vrpn_protocol.h"

namespace mocap::stream::vrpn {
namespace {

const uint8_t* U(const std::string& s) { return reinterpret_cast<const uint8_t*>(s.data()); }

uint32_t BeU32(const std::string& s, size_t at) {
  uint32_t v;
  std::memcpy(&v, s.data() + at, 4);
  return ntohl(v);
}

double BeF64(const std::string& s, size_t at) {
  uint64_t bits = 0;
  for (int i = 0; i < 8; ++i) bits = bits << 8 | static_cast<uint8_t>(s[at + i]);
  double v;
  std::memcpy(&v, &bits, 8);
  return v;
}

std::string ClientCookie(const char* magic, char mode = '0') {
  std::string c = std::string(magic) + "  " + mode;
  c.resize(kCookieSize, '\0');
  return c;
}

std::vector<ReceivedMessage> ReadAll(const std::string& bytes) {
  MessageReader r;
  std::vector<ReceivedMessage> out;
  EXPECT_EQ(r.Feed(U(bytes), bytes.size()), bytes.size());
  ReceivedMessage m;
  while (r.Next(&m)) out.push_back(m);
  EXPECT_FALSE(r.broken()) << r.reason();
  return out;
}

TEST(VrpnCookie, AsVrpnConnectionWritesAndChecksIt) {
  const std::string c = Cookie();
  ASSERT_EQ(c.size(), kCookieSize);
  EXPECT_EQ(std::string(c.c_str()), "vrpn: ver. 07.35  0");
  EXPECT_EQ(CheckCookie(U(c)), "");
  EXPECT_EQ(CheckCookie(U(ClientCookie("vrpn: ver. 07.38"))), "");  // minor versions differ: fine
  EXPECT_NE(CheckCookie(U(ClientCookie("vrpn: ver. 06.35"))).find("bad cookie"), std::string::npos);
  EXPECT_NE(CheckCookie(U(ClientCookie("vrpn: ver. 07.35", '7'))).find("log mode"), std::string::npos);
  EXPECT_NE(CheckCookie(U(std::string(kCookieSize, 'x'))), "");
}

TEST(VrpnMessage, HeaderPaddingAndPayloads) {
  const std::string m = Message(kPosQuat, 3, Timestamp{1700000000, 123456},
                                PosQuatPayload({1.5, -2.0, 0.25}, Eigen::Quaterniond(0.5, 0.5, 0.5, 0.5)), 77);
  ASSERT_EQ(m.size(), 24u + 64);
  EXPECT_EQ(BeU32(m, 0), 24u + 64);
  EXPECT_EQ(BeU32(m, 4), 1700000000u);
  EXPECT_EQ(BeU32(m, 8), 123456u);
  EXPECT_EQ(BeU32(m, 12), 3u);
  EXPECT_EQ(BeU32(m, 16), static_cast<uint32_t>(kPosQuat));
  EXPECT_EQ(BeU32(m, 20), 77u);
  EXPECT_EQ(BeU32(m, 24), 0u);  // sensor
  EXPECT_EQ(BeF64(m, 32), 1.5);
  EXPECT_EQ(BeF64(m, 40), -2.0);
  EXPECT_EQ(BeF64(m, 48), 0.25);
  for (int i = 0; i < 4; ++i) EXPECT_DOUBLE_EQ(BeF64(m, 56 + 8 * i), 0.5);
  // A description: the name's length with its NUL, the name, padding to 8 (length without it).
  const std::string d = Description(kSenderDescription, 2, "drone");
  EXPECT_EQ(BeU32(d, 0), 24u + 4 + 6);
  EXPECT_EQ(d.size(), 24u + 16);
  EXPECT_EQ(static_cast<int32_t>(BeU32(d, 16)), kSenderDescription);
  EXPECT_EQ(BeU32(d, 12), 2u);
  EXPECT_EQ(BeU32(d, 24), 6u);
  EXPECT_EQ(d.substr(28, 6), std::string("drone\0", 6));
  const std::string v = VelocityPayload({1, 2, 3}, Eigen::Quaterniond::Identity(), 0.004);
  ASSERT_EQ(v.size(), 72u);
  EXPECT_EQ(BeF64(v, 64), 0.004);
  EXPECT_EQ(FromNs(1'700'000'000'123'456'789ull).microseconds, 123456u);
}

TEST(VrpnReader, CutsAStreamCutAnywhere) {
  std::string stream;
  for (int i = 0; i < 5; ++i) stream += Message(i, 10 + i, Timestamp{1, 2}, std::string(static_cast<size_t>(i * 3), 'a' + i));
  for (size_t piece : {size_t{1}, size_t{5}, size_t{24}, size_t{1000}}) {
    MessageReader r;
    std::vector<ReceivedMessage> got;
    for (size_t at = 0; at < stream.size(); at += piece) {
      const size_t n = std::min(piece, stream.size() - at);
      EXPECT_EQ(r.Feed(U(stream) + at, n), n);
      ReceivedMessage m;
      while (r.Next(&m)) got.push_back(m);
    }
    ASSERT_EQ(got.size(), 5u) << piece;
    for (int i = 0; i < 5; ++i) {
      EXPECT_EQ(got[i].type, i);
      EXPECT_EQ(got[i].sender, 10 + i);
      EXPECT_EQ(got[i].payload, std::string(static_cast<size_t>(i * 3), 'a' + i));
    }
  }
}

TEST(VrpnReader, RefusesLengthsNoMessageHas) {
  for (uint32_t length : {0u, 23u, static_cast<uint32_t>(kMaxMessage + 1), 0xffffffffu}) {
    std::string m = Message(1, 1, Timestamp{}, "");
    const uint32_t be = htonl(length);
    std::memcpy(&m[0], &be, 4);
    MessageReader r;
    r.Feed(U(m), m.size());
    EXPECT_TRUE(r.broken()) << length;
    EXPECT_NE(r.reason().find("message length"), std::string::npos);
  }
}

TEST(VrpnSession, DescribesTrackersThenAnswersPings) {
  VrpnSession s({"drone", "wand"});
  std::string out;
  const std::string cookie = ClientCookie("vrpn: ver. 07.35");
  s.Receive(U(cookie), 10, 0, &out);  // half a cookie: nothing yet
  EXPECT_FALSE(s.connected());
  EXPECT_TRUE(out.empty());
  // The rest of the cookie, then the client's descriptions and a ping from its "wand" tracker.
  std::string rest = cookie.substr(10);
  rest += Description(kSenderDescription, 5, "wand");
  rest += Description(kTypeDescription, 9, "vrpn_Base ping_message");
  rest += Message(-3, 4000, Timestamp{}, std::string("127.0.0.1\0", 10));  // its UDP port: ignored
  rest += Message(9, 5, Timestamp{}, "");
  s.Receive(U(rest), rest.size(), 1'500'000'000'000'000'000ull, &out);
  ASSERT_TRUE(s.connected()) << s.close_reason();
  const std::vector<ReceivedMessage> sent = ReadAll(out);
  ASSERT_EQ(sent.size(), 2u + 3 + 1);
  EXPECT_EQ(sent[0].type, kSenderDescription);
  EXPECT_EQ(sent[0].payload.substr(4), std::string("drone\0", 6));
  EXPECT_EQ(sent[1].payload.substr(4), std::string("wand\0", 5));
  EXPECT_EQ(sent[2].type, kTypeDescription);
  EXPECT_EQ(sent[2].sender, kPosQuat);
  EXPECT_EQ(sent[2].payload.substr(4), std::string("vrpn_Tracker Pos_Quat\0", 22));
  EXPECT_EQ(sent[4].payload.substr(4), std::string("vrpn_Base pong_message\0", 23));
  EXPECT_EQ(sent[5].type, kPong);
  EXPECT_EQ(sent[5].sender, 1);  // our "wand"
  EXPECT_EQ(sent[5].time.seconds, 1'500'000'000u);
  EXPECT_EQ(s.pongs(), 1u);
  // A ping from a tracker this server does not have gets no pong.
  out.clear();
  const std::string other = Description(kSenderDescription, 6, "nobody") + Message(9, 6, Timestamp{}, "");
  s.Receive(U(other), other.size(), 0, &out);
  EXPECT_TRUE(out.empty());
  const std::string bye = Message(kDisconnectMessage, 0, Timestamp{}, "");
  s.Receive(U(bye), bye.size(), 0, &out);
  EXPECT_TRUE(s.closed());
}

TEST(VrpnSession, RefusesBadCookiesAndDescriptions) {
  {
    VrpnSession s({"a"});
    std::string out;
    const std::string c = ClientCookie("vrpn: ver. 08.00");
    s.Receive(U(c), c.size(), 0, &out);
    EXPECT_TRUE(s.closed());
    EXPECT_TRUE(out.empty());
  }
  {
    VrpnSession s({"a"});
    std::string out;
    std::string bytes = ClientCookie("vrpn: ver. 07.35");
    std::string lying = Description(kTypeDescription, 1, "abc");
    const uint32_t be = htonl(500);
    std::memcpy(&lying[24], &be, 4);  // name length beyond the message
    bytes += lying;
    s.Receive(U(bytes), bytes.size(), 0, &out);
    EXPECT_TRUE(s.closed());
    EXPECT_NE(s.close_reason().find("does not fit"), std::string::npos) << s.close_reason();
  }
  {
    VrpnSession s({"a"});
    std::string out;
    std::string bytes = ClientCookie("vrpn: ver. 07.35");
    for (int i = 0; i <= static_cast<int>(VrpnSession::kMaxRemoteNames); ++i)
      bytes += Description(kSenderDescription, i, "n" + std::to_string(i));
    s.Receive(U(bytes), bytes.size(), 0, &out);
    EXPECT_TRUE(s.closed());
    EXPECT_NE(s.close_reason().find("names described"), std::string::npos) << s.close_reason();
  }
}

}  // namespace
}  // namespace mocap::stream::vrpn

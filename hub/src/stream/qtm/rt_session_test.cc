// One client's protocol without sockets: the greeting, version negotiation, answers to every
// command, errors that keep the connection usable, unframeable garbage that closes it, streams
// at the rates asked for (TCP frames droppable, UDP to the right address), GetCurrentFrame
// before and after the first frame, and the state events.
#include "stream/qtm/rt_session.h"

#include <arpa/inet.h>

#include <gtest/gtest.h>

#include "stream/qtm/rt_test_util.h"

namespace mocap::stream::qtm {
namespace {

sockaddr_in Peer() {
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_port = htons(50000);
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  return a;
}

class Client {
 public:
  explicit Client(RtServerState* state) : state_(state), session_(Peer(), &out_) {}

  void Send(const std::string& command) { SendBytes(MakeStringPacket(PacketType::kCommand, command)); }
  void SendBytes(const std::string& bytes) {
    session_.Receive(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size(), *state_, &out_);
  }
  void Frame(const pipeline::LiveFrame& frame) {
    state_->latest = std::make_shared<pipeline::LiveFrame>(frame);
    state_->names.Update(frame);
    const RtEncoder encode = [&](uint32_t c) {
      return std::make_shared<const std::string>(EncodeDataPacket(frame, c, state_->names, 2));
    };
    session_.OnFrame(*state_, encode, &out_);
  }
  // Packets sent so far (and forgotten), with whether each was droppable.
  std::vector<testing::Packet> Take(std::vector<bool>* droppable = nullptr) {
    std::string bytes;
    for (const RtOutPacket& p : out_.tcp) {
      bytes += *p.bytes;
      if (droppable) droppable->push_back(p.droppable);
    }
    out_.tcp.clear();
    return testing::SplitPackets(&bytes);
  }
  std::vector<PacketPtr> TakeUdp() { return std::exchange(out_.udp, {}); }
  RtSession& session() { return session_; }
  RtOutput& out() { return out_; }

 private:
  RtServerState* state_;
  RtOutput out_;
  RtSession session_;
};

pipeline::LiveFrame FrameNumber(uint64_t n) {
  pipeline::LiveFrame f;
  f.frame_number = n;
  f.cameras = 2;
  pipeline::LivePoint p;
  p.position = {1, 2, 3};
  p.marker = 0;
  f.points.push_back(p);
  return f;
}

TEST(RtSession, GreetingVersionAndSimpleCommands) {
  RtServerState state;
  Client c(&state);
  std::vector<testing::Packet> got = c.Take();
  ASSERT_EQ(got.size(), 1u);
  EXPECT_EQ(got[0].type, 1u);
  EXPECT_EQ(got[0].Text(), "QTM RT Interface connected");

  c.Send("Version");
  c.Send("Version 1.25");
  c.Send("version");
  c.Send("ByteOrder");
  c.Send("QTMVersion");
  got = c.Take();
  ASSERT_EQ(got.size(), 5u);
  EXPECT_EQ(got[0].Text(), "Version is 1.1");
  EXPECT_EQ(got[1].Text(), "Version set to 1.25");
  EXPECT_EQ(got[2].Text(), "Version is 1.25");
  EXPECT_EQ(got[3].Text(), "Byte order is little endian");
  EXPECT_EQ(got[4].Text().rfind("QTM Version is mocap-hub", 0), 0u);
  for (const auto& p : got) EXPECT_EQ(p.type, 1u);

  c.Send("GetState");
  got = c.Take();
  ASSERT_EQ(got.size(), 1u);
  EXPECT_EQ(got[0].type, 6u);
  EXPECT_EQ(got[0].body, std::string(1, 2));  // no frames yet: Connection Closed
  state.flowing = true;
  c.Send("GetState");
  state.capturing = true;
  c.Send("GetState");
  got = c.Take();
  ASSERT_EQ(got.size(), 2u);
  EXPECT_EQ(got[0].body, std::string(1, 1));  // Connected
  EXPECT_EQ(got[1].body, std::string(1, 3));  // Capture Started

  c.Send("GetParameters 3D");
  got = c.Take();
  ASSERT_EQ(got.size(), 1u);
  EXPECT_EQ(got[0].type, 2u);
  EXPECT_EQ(got[0].Text().rfind("<QTM_Parameters_Ver_1.25>", 0), 0u);
}

TEST(RtSession, ErrorsKeepTheConnectionGarbageClosesIt) {
  RtServerState state;
  Client c(&state);
  c.Take();
  c.Send("Version 3.0");
  c.Send("Fly me to the moon");
  c.Send("StreamFrames AllFrames 2D");
  c.SendBytes(MakeStringPacket(PacketType::kXml, "<QTM_Settings/>"));
  c.SendBytes(MakePacket(PacketType::kData, "xyz"));
  c.SendBytes(MakePacket(PacketType::kCommand, std::string(kMaxCommandPacket + 1, 'A')));
  c.Send("ByteOrder");
  std::vector<testing::Packet> got = c.Take();
  ASSERT_EQ(got.size(), 7u);
  for (size_t i = 0; i < 6; ++i) {
    EXPECT_EQ(got[i].type, 0u) << i;
    EXPECT_FALSE(got[i].Text().empty());
  }
  EXPECT_EQ(got[0].Text(), "Version NOT supported");
  EXPECT_EQ(got[6].Text(), "Byte order is little endian");
  EXPECT_FALSE(c.out().close);
  EXPECT_EQ(c.session().errors(), 6u);

  std::string garbage = "GET / HTTP/1.1\r\n\r\n";  // "GET " is a size of 542393671
  c.SendBytes(garbage);
  got = c.Take();
  ASSERT_EQ(got.size(), 1u);
  EXPECT_EQ(got[0].type, 0u);
  EXPECT_TRUE(c.out().close);
}

TEST(RtSession, QuitSaysGoodbyeAndCloses) {
  RtServerState state;
  Client c(&state);
  c.Take();
  c.Send("Quit");
  const std::vector<testing::Packet> got = c.Take();
  ASSERT_EQ(got.size(), 1u);
  EXPECT_EQ(got[0].Text(), "Bye bye");
  EXPECT_TRUE(c.out().close);
}

TEST(RtSession, StreamsAtTheRateAskedAndStops) {
  RtServerState state;
  state.system.rate_hz = 100;
  state.flowing = true;
  Client c(&state);
  c.Take();
  c.Send("StreamFrames AllFrames 3D");
  EXPECT_TRUE(c.Take().empty());  // frames flow: no answer but the frames
  for (int i = 0; i < 5; ++i) c.Frame(FrameNumber(i));
  std::vector<bool> droppable;
  std::vector<testing::Packet> got = c.Take(&droppable);
  ASSERT_EQ(got.size(), 5u);
  for (size_t i = 0; i < got.size(); ++i) {
    EXPECT_EQ(got[i].type, 3u);
    EXPECT_TRUE(droppable[i]);
    EXPECT_EQ(testing::ReadFrame(got[i].body).frame_number, i);
  }

  c.Send("StreamFrames FrequencyDivisor:3 3D");
  for (int i = 0; i < 9; ++i) c.Frame(FrameNumber(i));
  got = c.Take();
  ASSERT_EQ(got.size(), 3u);
  EXPECT_EQ(testing::ReadFrame(got[1].body).frame_number, 3u);

  c.Send("StreamFrames Frequency:25 3D");
  for (int i = 0; i < 100; ++i) c.Frame(FrameNumber(i));
  EXPECT_EQ(c.Take().size(), 25u);

  c.Send("StreamFrames Frequency:500 3D");  // above the rate: every frame
  for (int i = 0; i < 10; ++i) c.Frame(FrameNumber(i));
  EXPECT_EQ(c.Take().size(), 10u);

  c.Send("StreamFrames Stop");
  for (int i = 0; i < 10; ++i) c.Frame(FrameNumber(i));
  EXPECT_TRUE(c.Take().empty());
  EXPECT_FALSE(c.session().streaming());
}

TEST(RtSession, UdpStreamsGoToTheClientOrTheAddressGiven) {
  RtServerState state;
  state.flowing = true;
  Client c(&state);
  c.Take();
  c.Send("StreamFrames AllFrames UDP:40001 3DNoLabels");
  c.Frame(FrameNumber(1));
  EXPECT_TRUE(c.Take().empty());
  EXPECT_EQ(c.TakeUdp().size(), 1u);
  EXPECT_EQ(ntohs(c.session().udp_target().sin_port), 40001);
  EXPECT_EQ(ntohl(c.session().udp_target().sin_addr.s_addr), INADDR_LOOPBACK);
  c.Send("StreamFrames AllFrames UDP:10.1.2.3:40002 3D");
  c.Frame(FrameNumber(2));
  EXPECT_EQ(c.TakeUdp().size(), 1u);
  char text[INET_ADDRSTRLEN];
  inet_ntop(AF_INET, &c.session().udp_target().sin_addr, text, sizeof text);
  EXPECT_STREQ(text, "10.1.2.3");
}

TEST(RtSession, CurrentFrameOrNoMoreData) {
  RtServerState state;
  Client c(&state);
  c.Take();
  c.Send("GetCurrentFrame 3D 6D");
  std::vector<testing::Packet> got = c.Take();
  ASSERT_EQ(got.size(), 1u);
  EXPECT_EQ(got[0].type, 4u);  // no frames flowing: No More Data
  c.Frame(FrameNumber(41));
  EXPECT_TRUE(c.Take().empty());  // nothing unasked
  state.flowing = true;
  c.Send("GetCurrentFrame 3D 6D");
  std::vector<bool> droppable;
  got = c.Take(&droppable);
  ASSERT_EQ(got.size(), 1u);
  EXPECT_FALSE(droppable[0]);  // an answer, never shed
  testing::Frame f = testing::ReadFrame(got[0].body);
  EXPECT_EQ(f.frame_number, 41u);
  ASSERT_EQ(f.components.size(), 2u);
  EXPECT_EQ(f.components[1].type, 5u);
  c.Frame(FrameNumber(42));
  EXPECT_TRUE(c.Take().empty());  // polling: no frame unasked
  c.Send("GetCurrentFrame 3DRes");
  got = c.Take();
  ASSERT_EQ(got.size(), 1u);
  EXPECT_EQ(testing::ReadFrame(got[0].body).frame_number, 42u);
}

TEST(RtSession, EventsAndNoMoreData) {
  RtServerState state;
  Client c(&state);
  c.Take();
  c.Send("StreamFrames AllFrames 3D");
  std::vector<testing::Packet> got = c.Take();
  ASSERT_EQ(got.size(), 1u);
  EXPECT_EQ(got[0].type, 4u);  // nothing flowing yet: No More Data
  c.session().OnEvent(RtEvent::kConnected, &c.out());
  c.session().OnEvent(RtEvent::kConnectionClosed, &c.out());
  got = c.Take();
  ASSERT_EQ(got.size(), 3u);
  EXPECT_EQ(got[0].type, 6u);
  EXPECT_EQ(got[0].body, std::string(1, 1));
  EXPECT_EQ(got[1].body, std::string(1, 2));
  EXPECT_EQ(got[2].type, 4u);
}

}  // namespace
}  // namespace mocap::stream::qtm

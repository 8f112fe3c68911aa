// The pure parts of the Qualisys RT server: packet framing with bounded memory, the command
// parser (every command and component, and the ways to get them wrong), data packets laid out as
// the protocol documents them, and the parameter XML.
#include <cmath>

#include <gtest/gtest.h>

#include "stream/qtm/rt_command.h"
#include "stream/qtm/rt_frame.h"
#include "stream/qtm/rt_packet.h"
#include "stream/qtm/rt_parameters.h"
#include "stream/qtm/rt_test_util.h"

namespace mocap::stream::qtm {
namespace {

using testing::F32;
using testing::U32;

TEST(RtPacket, HeaderCarriesTotalSizeAndType) {
  const std::string p = MakeStringPacket(PacketType::kCommand, "Version 1.2");
  EXPECT_EQ(p.size(), 20u);  // the protocol's own example: 8 + "Version 1.2" + NUL
  EXPECT_EQ(U32(p, 0), 20u);
  EXPECT_EQ(U32(p, 4), 1u);
  EXPECT_EQ(p.back(), '\0');
  const std::string e = MakeEventPacket(RtEvent::kCaptureStarted);
  EXPECT_EQ(U32(e, 0), 9u);
  EXPECT_EQ(U32(e, 4), 6u);
  EXPECT_EQ(e[8], 3);
}

TEST(RtPacket, ReaderReassemblesAcrossAnySplit) {
  const std::string stream = MakeStringPacket(PacketType::kCommand, "GetState") +
                             MakeStringPacket(PacketType::kCommand, "ByteOrder");
  for (size_t step = 1; step <= stream.size(); ++step) {
    PacketReader reader;
    std::vector<std::string> bodies;
    size_t at = 0;
    while (at < stream.size()) {
      const size_t n = std::min(step, stream.size() - at);
      size_t used = 0;
      while (used < n) {
        used += reader.Feed(reinterpret_cast<const uint8_t*>(stream.data()) + at + used, n - used);
        ReceivedPacket p;
        while (reader.Next(&p)) bodies.push_back(p.body);
      }
      at += n;
    }
    ASSERT_EQ(bodies.size(), 2u) << "step " << step;
    EXPECT_EQ(bodies[0], std::string("GetState") + '\0');
    EXPECT_EQ(bodies[1], std::string("ByteOrder") + '\0');
  }
}

TEST(RtPacket, OversizedCommandIsSkippedUnbufferedAndTheStreamGoesOn) {
  const std::string big = MakePacket(PacketType::kCommand, std::string(kMaxCommandPacket + 100, 'x'));
  const std::string next = MakeStringPacket(PacketType::kCommand, "GetState");
  const std::string stream = big + next;
  PacketReader reader;
  std::vector<ReceivedPacket> got;
  size_t at = 0, most = 0;
  while (at < stream.size()) {
    const size_t n = std::min<size_t>(1000, stream.size() - at);
    size_t used = 0;
    while (used < n) {
      used += reader.Feed(reinterpret_cast<const uint8_t*>(stream.data()) + at + used, n - used);
      most = std::max(most, reader.buffered());
      ReceivedPacket p;
      while (reader.Next(&p)) got.push_back(p);
    }
    at += n;
  }
  ASSERT_EQ(got.size(), 2u);
  EXPECT_TRUE(got[0].too_large);
  EXPECT_TRUE(got[0].body.empty());
  EXPECT_FALSE(got[1].too_large);
  EXPECT_LE(most, kHeaderSize + kMaxCommandPacket);
  EXPECT_FALSE(reader.broken());
}

TEST(RtPacket, ImpossibleSizesBreakTheStream) {
  for (uint32_t size : {0u, 7u, static_cast<uint32_t>(kMaxFramedPacket + 1), 0xffffffffu}) {
    std::string header;
    PutU32(&header, size);
    PutU32(&header, 1);
    PacketReader reader;
    reader.Feed(reinterpret_cast<const uint8_t*>(header.data()), header.size());
    EXPECT_TRUE(reader.broken()) << size;
    EXPECT_EQ(reader.broken_size(), size);
  }
}

TEST(RtCommand, EveryCommandTheServerHonours) {
  Command c = ParseCommand(std::string("Version 1.25") + '\0');
  ASSERT_TRUE(c.ok) << c.error;
  EXPECT_EQ(c.kind, CommandKind::kVersion);
  EXPECT_EQ(c.version_minor, 25);
  c = ParseCommand("version");
  EXPECT_TRUE(c.ok && c.version_minor == 0);
  EXPECT_EQ(ParseCommand("QTMVERSION").kind, CommandKind::kQtmVersion);
  EXPECT_EQ(ParseCommand("byteorder").kind, CommandKind::kByteOrder);
  EXPECT_EQ(ParseCommand("GetState").kind, CommandKind::kGetState);
  EXPECT_EQ(ParseCommand("Disconnect").kind, CommandKind::kQuit);
  c = ParseCommand("GetParameters General 3D");
  ASSERT_TRUE(c.ok);
  EXPECT_EQ(c.parameters, kGeneral | k3dParameters);
  EXPECT_EQ(ParseCommand("getparameters all").parameters, kAllParameters);
  c = ParseCommand("GetCurrentFrame 3D 6DEulerRes");
  ASSERT_TRUE(c.ok);
  EXPECT_EQ(c.components, k3d | k6dEulerRes);
  c = ParseCommand("StreamFrames  AllFrames\t3DNoLabelsRes 6DRes");
  ASSERT_TRUE(c.ok) << c.error;
  EXPECT_EQ(c.kind, CommandKind::kStreamFrames);
  EXPECT_EQ(c.rate, FrameRate::kAllFrames);
  EXPECT_FALSE(c.udp);
  EXPECT_EQ(c.components, k3dNoLabelsRes | k6dRes);
  c = ParseCommand("StreamFrames Frequency:30 UDP:2234 3D");
  ASSERT_TRUE(c.ok) << c.error;
  EXPECT_EQ(c.rate, FrameRate::kFrequency);
  EXPECT_EQ(c.rate_value, 30u);
  EXPECT_TRUE(c.udp);
  EXPECT_TRUE(c.udp_address.empty());
  EXPECT_EQ(c.udp_port, 2234);
  c = ParseCommand("streamframes frequencydivisor:4 udp:127.0.0.1:40000 all");
  ASSERT_TRUE(c.ok) << c.error;
  EXPECT_EQ(c.rate, FrameRate::kFrequencyDivisor);
  EXPECT_EQ(c.rate_value, 4u);
  EXPECT_EQ(c.udp_address, "127.0.0.1");
  EXPECT_EQ(c.udp_port, 40000);
  EXPECT_EQ(c.components, kAllComponents);
  EXPECT_EQ(ParseCommand("StreamFrames Stop").kind, CommandKind::kStreamFramesStop);
}

TEST(RtCommand, EveryWrongCommandGetsAReason) {
  const char* bad[] = {"", "   ", "Bogus", "Version 2.0", "Version 1.0", "Version 1.100", "Version x", "Version 1.2 1.3",
                       "ByteOrder now", "GetParameters", "GetParameters Analog", "GetParameters 7D",
                       "GetCurrentFrame", "GetCurrentFrame 2D", "GetCurrentFrame 3D Foo", "StreamFrames",
                       "StreamFrames AllFrames", "StreamFrames Sometimes 3D", "StreamFrames Frequency:0 3D",
                       "StreamFrames Frequency:abc 3D", "StreamFrames FrequencyDivisor:-1 3D",
                       "StreamFrames AllFrames UDP 3D", "StreamFrames AllFrames UDP:80 3D",
                       "StreamFrames AllFrames UDP:99999 3D", "StreamFrames AllFrames UDP:nowhere:5000 3D",
                       "StreamFrames AllFrames UDP:5000", "StreamFrames AllFrames Analog:1,2", "TakeControl",
                       "Start", "Save x.qtm"};
  for (const char* text : bad) {
    const Command c = ParseCommand(text);
    EXPECT_FALSE(c.ok) << text;
    EXPECT_FALSE(c.error.empty()) << text;
  }
  EXPECT_NE(ParseCommand("Start").error.find("not supported"), std::string::npos);
  EXPECT_NE(ParseCommand("GetCurrentFrame Analog").error.find("not available"), std::string::npos);
  EXPECT_FALSE(ParseCommand(std::string(600, 'a')).ok);
  EXPECT_FALSE(ParseCommand(std::string("Get\x01State")).ok);
  EXPECT_FALSE(ParseCommand("GetState \xff").ok);
  std::string many = "GetParameters";
  for (int i = 0; i < 40; ++i) many += " 3D";
  EXPECT_FALSE(ParseCommand(many).ok);
}

pipeline::LivePoint Point(double x, double y, double z, int marker, uint64_t id = 0, double rms = 0.25) {
  pipeline::LivePoint p;
  p.position = {x, y, z};
  p.marker = marker;
  p.id = id;
  p.rms_px = rms;
  p.views = 3;
  return p;
}

TEST(RtFrame, LabelledComponentsFollowTheLabelsWithNanForUnseen) {
  pipeline::LiveFrame first;
  first.frame_number = 7;
  first.trigger_time_ns = 1'234'567'890;
  first.cameras = 4;
  first.points = {Point(1, 2, 3, 4, 50), Point(4, 5, 6, 1, 20)};
  RtNames names;
  names.Update(first);
  pipeline::LiveFrame second = first;
  second.frame_number = 8;
  second.cameras = 3;
  second.points = {Point(7, 8, 9, 1, 20), Point(10, 11, 12, -1, 5), Point(13, 14, 15, 9, 90)};
  names.Update(second);
  ASSERT_EQ(names.label_count(), 3u);
  EXPECT_EQ(names.label_name(0), "T50");  // confirmed tracks by id, provisional ones left out
  EXPECT_EQ(names.label_name(1), "T20");
  EXPECT_EQ(names.label_name(2), "T90");

  std::string packet = EncodeDataPacket(second, k3d | k3dRes, names, 4);
  const std::vector<testing::Packet> packets = testing::SplitPackets(&packet);
  ASSERT_EQ(packets.size(), 1u);
  EXPECT_EQ(packets[0].type, 3u);
  const testing::Frame f = testing::ReadFrame(packets[0].body);
  EXPECT_EQ(f.timestamp, 1'234'567u);
  EXPECT_EQ(f.frame_number, 8u);
  ASSERT_EQ(f.components.size(), 2u);
  const testing::Component& c3 = f.components[0];
  EXPECT_EQ(c3.type, 1u);
  EXPECT_EQ(c3.count, 3u);
  EXPECT_EQ(c3.drop, 250);  // one camera of four missing
  ASSERT_EQ(c3.data.size(), 3u * 12);
  EXPECT_EQ(U32(c3.data, 0), 0xffffffffu);  // T50 not seen: all bits set
  EXPECT_TRUE(std::isnan(F32(c3.data, 4)));
  EXPECT_FLOAT_EQ(F32(c3.data, 12), 7.0f);  // T20
  EXPECT_FLOAT_EQ(F32(c3.data, 32), 15.0f);  // T90's z
  const testing::Component& res = f.components[1];
  EXPECT_EQ(res.type, 9u);
  ASSERT_EQ(res.data.size(), 3u * 16);
  EXPECT_FLOAT_EQ(F32(res.data, 16 + 12), 0.25f);
}

TEST(RtFrame, WithAMarkerSetTheLabelsAreItsNames) {
  pipeline::LiveFrame frame;
  frame.frame_number = 3;
  frame.cameras = 4;
  frame.label_names = std::make_shared<const std::vector<std::string>>(std::vector<std::string>{"R.ASIS", "L&ASIS", "Head"});
  frame.points = {Point(1, 2, 3, 0), Point(4, 5, 6, 1), Point(7, 8, 9, -1, 3)};
  frame.points[0].label = 2;  // Head
  frame.points[2].label = 0;  // R.ASIS, a provisional point named by its segment partners
  RtNames names;
  names.Update(frame);
  ASSERT_EQ(names.label_count(), 3u);
  EXPECT_EQ(names.label_name(1), "L&ASIS");
  std::string packet = EncodeDataPacket(frame, k3d, names, 4);
  const std::vector<testing::Packet> packets = testing::SplitPackets(&packet);
  ASSERT_EQ(packets.size(), 1u);
  const testing::Frame f = testing::ReadFrame(packets[0].body);
  ASSERT_EQ(f.components.size(), 1u);
  const testing::Component& c = f.components[0];
  ASSERT_EQ(c.count, 3u);
  EXPECT_FLOAT_EQ(F32(c.data, 0), 7.0f);   // R.ASIS
  EXPECT_TRUE(std::isnan(F32(c.data, 12)));  // L&ASIS: no point has it
  EXPECT_FLOAT_EQ(F32(c.data, 24), 1.0f);  // Head
  RtSystem system;
  system.rate_hz = 100.0;
  const std::string xml = ParametersXml(system, names, k3dParameters, 25);
  EXPECT_NE(xml.find("<Labels>3</Labels>"), std::string::npos);
  EXPECT_NE(xml.find("<Name>R.ASIS</Name>"), std::string::npos);
  EXPECT_NE(xml.find("<Name>L&amp;ASIS</Name>"), std::string::npos);
}

TEST(RtFrame, NoLabelsCarryEveryPointWithItsTrackId) {
  pipeline::LiveFrame frame;
  frame.points = {Point(1, 2, 3, 4, 40), Point(4, 5, 6, -1, 77, 0.5), Point(7, 8, 9, -1)};
  RtNames names;
  names.Update(frame);
  std::string packet = EncodeDataPacket(frame, k3dNoLabels | k3dNoLabelsRes, names, 0);
  const testing::Frame f = testing::ReadFrame(testing::SplitPackets(&packet).at(0).body);
  ASSERT_EQ(f.components.size(), 2u);
  EXPECT_EQ(f.components[0].type, 2u);
  EXPECT_EQ(f.components[0].count, 3u);
  EXPECT_EQ(U32(f.components[0].data, 12), 40u);
  EXPECT_EQ(U32(f.components[0].data, 28), 77u);
  EXPECT_EQ(U32(f.components[0].data, 44), 0u);
  EXPECT_EQ(f.components[1].type, 10u);
  EXPECT_FLOAT_EQ(F32(f.components[1].data, 20 + 16), 0.5f);
  // Track 77 confirmed (as marker column 6) keeps its id; ids past 32 bits wrap past 0.
  frame.points = {Point(4, 5, 7, 6, 77), Point(0, 0, 0, -1, (uint64_t{1} << 32) + 2)};
  packet = EncodeDataPacket(frame, k3dNoLabels, names, 0);
  const testing::Frame g = testing::ReadFrame(testing::SplitPackets(&packet).at(0).body);
  EXPECT_EQ(U32(g.components[0].data, 12), 77u);
  EXPECT_EQ(U32(g.components[0].data, 28), 3u);
}

TEST(RtFrame, SixDComponentsWithAndWithoutBodies) {
  pipeline::LiveFrame frame;
  RtNames names;
  names.Update(frame);
  std::string packet = EncodeDataPacket(frame, k6d | k6dEuler | k6dRes | k6dEulerRes, names, 0);
  testing::Frame f = testing::ReadFrame(testing::SplitPackets(&packet).at(0).body);
  ASSERT_EQ(f.components.size(), 4u);
  const uint32_t types[] = {5, 6, 11, 12};
  for (size_t i = 0; i < 4; ++i) {
    EXPECT_EQ(f.components[i].type, types[i]);
    EXPECT_EQ(f.components[i].count, 0u);
    EXPECT_TRUE(f.components[i].data.empty());
  }

  const Eigen::Matrix3d r = (Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitX()) *
                             Eigen::AngleAxisd(-0.2, Eigen::Vector3d::UnitY()) *
                             Eigen::AngleAxisd(1.1, Eigen::Vector3d::UnitZ())).toRotationMatrix();
  pipeline::LiveBody tracked;
  tracked.id = 2;
  tracked.name = "wand";
  tracked.tracked = true;
  tracked.position = {10, 20, 30};
  tracked.orientation = Eigen::Quaterniond(r);
  tracked.mean_error_mm = 0.4;
  pipeline::LiveBody lost;
  lost.id = 1;
  lost.name = "hat";
  frame.bodies = {tracked, lost};
  names.Update(frame);
  packet = EncodeDataPacket(frame, k6dRes | k6dEuler, names, 0);
  f = testing::ReadFrame(testing::SplitPackets(&packet).at(0).body);
  ASSERT_EQ(f.components.size(), 2u);
  const testing::Component& euler = f.components[0];
  EXPECT_EQ(euler.count, 2u);
  ASSERT_EQ(euler.data.size(), 2u * 24);
  EXPECT_TRUE(std::isnan(F32(euler.data, 0)));  // body 1 (hat) not tracked
  EXPECT_FLOAT_EQ(F32(euler.data, 24), 10.0f);
  EXPECT_NEAR(F32(euler.data, 36), 0.3 * 180 / M_PI, 1e-4);
  EXPECT_NEAR(F32(euler.data, 40), -0.2 * 180 / M_PI, 1e-4);
  EXPECT_NEAR(F32(euler.data, 44), 1.1 * 180 / M_PI, 1e-4);
  const testing::Component& res = f.components[1];
  EXPECT_EQ(res.type, 11u);
  ASSERT_EQ(res.data.size(), 2u * 52);
  // Column by column: element (row, col) at 12 + 4 * (3 * col + row).
  for (int col = 0; col < 3; ++col)
    for (int row = 0; row < 3; ++row)
      EXPECT_NEAR(F32(res.data, 52 + 12 + 4 * (3 * col + row)), r(row, col), 1e-6);
  EXPECT_FLOAT_EQ(F32(res.data, 52 + 48), 0.4f);
}

TEST(RtFrame, EulerAnglesRoundTripIncludingGimbalLock) {
  for (double pitch : {-1.2, 0.0, 0.7, M_PI / 2}) {
    const Eigen::Matrix3d r = (Eigen::AngleAxisd(0.4, Eigen::Vector3d::UnitX()) *
                               Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
                               Eigen::AngleAxisd(-0.9, Eigen::Vector3d::UnitZ())).toRotationMatrix();
    const Eigen::Vector3d a = EulerDegrees(r) * M_PI / 180;
    const Eigen::Matrix3d back = (Eigen::AngleAxisd(a[0], Eigen::Vector3d::UnitX()) *
                                  Eigen::AngleAxisd(a[1], Eigen::Vector3d::UnitY()) *
                                  Eigen::AngleAxisd(a[2], Eigen::Vector3d::UnitZ())).toRotationMatrix();
    EXPECT_LT((back - r).norm(), 1e-7) << pitch;  // asin near 1 keeps sqrt(eps)
  }
}

Rig RingRig(const Eigen::Vector3d& up) {
  Rig rig;
  for (int i = 0; i < 4; ++i) {
    Camera c;
    c.id = static_cast<uint32_t>(i + 1);
    c.intrinsics.width = 640;
    c.intrinsics.height = 400;
    // Looking horizontally at the origin with image up = world up.
    const double a = i * M_PI / 2;
    const Eigen::Vector3d side = up.unitOrthogonal();
    const Eigen::Vector3d forward = std::cos(a) * side + std::sin(a) * up.cross(side);
    Eigen::Matrix3d cam_from_world;
    cam_from_world.row(0) = forward.cross(-up).transpose();
    cam_from_world.row(1) = (-up).transpose();
    cam_from_world.row(2) = forward.transpose();
    c.rotation = cam_from_world;
    c.translation = -cam_from_world * (-3000 * forward);
    rig.cameras.push_back(c);
  }
  return rig;
}

TEST(RtParameters, AxisUpwardsFromTheCameras) {
  EXPECT_EQ(AxisUpwards(RingRig(Eigen::Vector3d::UnitZ())), "+Z");
  EXPECT_EQ(AxisUpwards(RingRig(Eigen::Vector3d::UnitY())), "+Y");
  EXPECT_EQ(AxisUpwards(RingRig(-Eigen::Vector3d::UnitX())), "-X");
  EXPECT_EQ(AxisUpwards(Rig{}), "+Z");
}

TEST(RtParameters, XmlBlocksAsAsked) {
  RtSystem system;
  system.rate_hz = 120;
  system.rig = RingRig(Eigen::Vector3d::UnitZ());
  system.axis_upwards = AxisUpwards(system.rig);
  RtNames names;
  pipeline::LiveFrame frame;
  frame.points = {Point(0, 0, 0, 2, 3)};
  pipeline::LiveBody body;
  body.id = 1;
  body.name = "a<b&c";
  frame.bodies = {body};
  names.Update(frame);
  const std::string all = ParametersXml(system, names, kAllParameters, 25);
  EXPECT_EQ(all.rfind("<QTM_Parameters_Ver_1.25>", 0), 0u);
  EXPECT_NE(all.find("</QTM_Parameters_Ver_1.25>"), std::string::npos);
  EXPECT_NE(all.find("<Frequency>120</Frequency>"), std::string::npos);
  EXPECT_NE(all.find("<ID>4</ID>"), std::string::npos);
  EXPECT_NE(all.find("<AxisUpwards>+Z</AxisUpwards>"), std::string::npos);
  EXPECT_NE(all.find("<Labels>1</Labels>"), std::string::npos);
  EXPECT_NE(all.find("<Name>T3</Name>"), std::string::npos);
  EXPECT_NE(all.find("<RGBColor>255</RGBColor>"), std::string::npos);  // red, as a decimal integer
  EXPECT_NE(all.find("<RealTime_Processing_Actions>"), std::string::npos);
  EXPECT_NE(all.find("<Marker_Threshold><Current>0</Current>"), std::string::npos);
  EXPECT_NE(all.find("<Signal_Edge>Positive</Signal_Edge>"), std::string::npos);
  EXPECT_NE(all.find("<Bodies>1</Bodies>"), std::string::npos);
  EXPECT_NE(all.find("<Name>a&lt;b&amp;c</Name>"), std::string::npos);
  EXPECT_NE(all.find("<Color R=\"255\" G=\"0\" B=\"0\"/>"), std::string::npos);
  EXPECT_NE(all.find("<Data_origin X=\"0\" Y=\"0\" Z=\"0\" Relative_body=\"0\">0</Data_origin>"), std::string::npos);
  // Camera 1 sits 3 m out along the ring; its centre is in the XML.
  const Eigen::Vector3d centre = system.rig.cameras[0].CenterInWorld();
  char x[64];
  std::snprintf(x, sizeof x, "<X>%.6g</X>", centre.x());
  EXPECT_NE(all.find(x), std::string::npos) << x;
  const std::string only3d = ParametersXml(system, names, k3dParameters, 1);
  EXPECT_EQ(only3d.find("<General>"), std::string::npos);
  EXPECT_EQ(only3d.find("<The_6D>"), std::string::npos);
  EXPECT_NE(only3d.find("<QTM_Parameters_Ver_1.1>"), std::string::npos);
  EXPECT_EQ(XmlEscape(std::string("q\"'\x01")), "q&quot;&apos;");
}

}  // namespace
}  // namespace mocap::stream::qtm

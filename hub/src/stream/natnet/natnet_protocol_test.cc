// NatNet without sockets: requests as the clients send them (libmotioncapture's empty connect,
// the NatNet SDK's 271-byte connect asking for 4.1, command lines), refusals of malformed
// datagrams, the command answers, and model definitions and frames read back field by field
// with a reader written here from the protocol's layout (the real clients read them in
// tests/stream/natnet_vrpn_vmc_test.py).
#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "stream/natnet/natnet_commands.h"
#include "stream/natnet/natnet_frame.h"
#include "stream/natnet/natnet_packet.h"

namespace mocap::stream::natnet {
namespace {

std::string Packet(uint16_t id, const std::string& payload) {
  std::string p;
  p.push_back(static_cast<char>(id & 0xff));
  p.push_back(static_cast<char>(id >> 8));
  p.push_back(static_cast<char>(payload.size() & 0xff));
  p.push_back(static_cast<char>(payload.size() >> 8));
  return p + payload;
}

Request Parse(const std::string& bytes) {
  return ParseRequest(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size());
}

// Little-endian reader that fails the test instead of reading past the end.
struct Reader {
  const std::string& b;
  size_t at = 0;
  template <typename T>
  T Get() {
    T v{};
    EXPECT_LE(at + sizeof(T), b.size()) << "read past the end";
    if (at + sizeof(T) > b.size()) return v;
    std::memcpy(&v, b.data() + at, sizeof(T));
    at += sizeof(T);
    return v;
  }
  std::string Str() {
    const size_t end = b.find('\0', at);
    EXPECT_NE(end, std::string::npos);
    std::string s = b.substr(at, end - at);
    at = end + 1;
    return s;
  }
};

Model TwoBodies() {
  Model m;
  m.rate_hz = 240;
  RigidBodyDefinition a;
  a.name = "drone";
  a.markers = {{0, 0, 0}, {100, 0, 0}, {0, 80, 0}};
  a.pivot = {10, 20, 30};
  RigidBodyDefinition b;
  b.name = "wand";
  b.markers = {{0, 0, 0}, {0, 0, 50}, {40, 0, 0}, {0, 60, 0}};
  m.bodies = {a, b};
  return m;
}

pipeline::LiveFrame OneFrame() {
  pipeline::LiveFrame f;
  f.frame_number = 1234;
  f.trigger_time_ns = 1'700'000'000'123'456'789ull;
  f.last_receive_ns = f.trigger_time_ns + 2'000'000;
  f.publish_ns = f.last_receive_ns + 300'000;
  pipeline::LivePoint confirmed;
  confirmed.position = {1000, 2000, 3000};
  confirmed.marker = 4;
  confirmed.id = 9;
  pipeline::LivePoint loose;
  loose.position = {-5, 6, -7};
  f.points = {confirmed, loose};
  pipeline::LiveBody drone;
  drone.id = 1;
  drone.name = "drone";
  drone.tracked = true;
  drone.position = {100, 200, 300};
  drone.orientation = Eigen::Quaterniond(Eigen::AngleAxisd(0.5, Eigen::Vector3d(0, 0, 1)));
  drone.mean_error_mm = 0.25;
  pipeline::LiveBody wand;
  wand.id = 2;
  wand.name = "wand";
  f.bodies = {drone, wand};
  return f;
}

TEST(NatNetRequest, ConnectsAsBothClientsSendIt) {
  // libmotioncapture: a bare header.
  Request bare = Parse(Packet(kConnect, ""));
  ASSERT_TRUE(bare.ok) << bare.reason;
  EXPECT_EQ(bare.id, kConnect);
  EXPECT_FALSE(bare.asked_version);
  // The NatNet SDK's Python client: "Ping", then the connection options asking for 4.1.
  std::string sdk(271, '\0');
  sdk.replace(0, 4, "Ping");
  sdk[265] = 4;
  sdk[266] = 1;
  Request asked = Parse(Packet(kConnect, sdk));
  ASSERT_TRUE(asked.ok);
  EXPECT_TRUE(asked.asked_version);
  EXPECT_EQ(asked.asked, (Version{4, 1}));
}

TEST(NatNetRequest, CommandLines) {
  const Request r = Parse(Packet(kRequest, std::string("Bitstream,3.1") + '\0'));
  ASSERT_TRUE(r.ok);
  EXPECT_EQ(r.command, "Bitstream,3.1");
  // Without its NUL the line ends with the payload.
  EXPECT_EQ(Parse(Packet(kRequest, "FrameRate")).command, "FrameRate");
}

TEST(NatNetRequest, MalformedDatagramsAreRefusedWithAReason) {
  EXPECT_NE(Parse("\x02").reason.find("shorter than a header"), std::string::npos);
  std::string lying = Packet(kRequest, "abc");
  lying[2] = 50;  // claims 50 payload bytes, has 3
  const Request r = Parse(lying);
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.reason.find("50 payload bytes"), std::string::npos) << r.reason;
  EXPECT_FALSE(Parse(Packet(kRequest, std::string(1, '\0'))).ok);
  EXPECT_NE(Parse(Packet(kRequest, "Frame\x01Rate")).reason.find("printable"), std::string::npos);
  EXPECT_FALSE(Parse(Packet(kRequest, std::string(5000, 'a'))).ok);
}

TEST(NatNetVersion, ParsesAndBounds) {
  Version v;
  EXPECT_TRUE(ParseVersion("3.0", &v));
  EXPECT_EQ(v, (Version{3, 0}));
  EXPECT_TRUE(ParseVersion("4.1.0.0", &v));
  EXPECT_EQ(v, (Version{4, 1}));
  for (const char* bad : {"", "4", "4.1.0", "4.1x", "-1.0", "4,1", " 4.1", "999.1"}) EXPECT_FALSE(ParseVersion(bad, &v)) << bad;
  EXPECT_FALSE(Supported(Version{2, 9}));
  EXPECT_FALSE(Supported(Version{4, 2}));
}

TEST(NatNetCommands, AnswersAsMotive) {
  const Model model = TwoBodies();
  CommandState state;
  auto answer = [&](const std::string& line) {
    Request r;
    r.ok = true;
    r.id = kRequest;
    r.command = line;
    return Answer(r, model, &state);
  };
  auto int_of = [](const std::string& p) {
    EXPECT_EQ(p.size(), 8u);
    int32_t v = -99;
    std::memcpy(&v, p.data() + 4, 4);
    return v;
  };
  auto float_of = [](const std::string& p) {
    EXPECT_EQ(p.size(), 8u);
    float v = -99;
    std::memcpy(&v, p.data() + 4, 4);
    return v;
  };
  EXPECT_EQ(answer("Bitstream").packet, Packet(kResponse, std::string("Bitstream,4.1") + '\0'));
  EXPECT_EQ(int_of(answer("Bitstream,3.1").packet), 0);
  EXPECT_EQ(state.version, (Version{3, 1}));
  EXPECT_EQ(answer("bitstream").packet, Packet(kResponse, std::string("Bitstream,3.1") + '\0'));
  const Reply refused = answer("Bitstream,2.9");
  EXPECT_EQ(int_of(refused.packet), 1);
  EXPECT_TRUE(refused.failed);
  EXPECT_EQ(state.version, (Version{3, 1}));
  EXPECT_EQ(float_of(answer("UnitsToMillimeters").packet), 1000.0f);
  EXPECT_EQ(float_of(answer("FrameRate").packet), 240.0f);
  EXPECT_EQ(int_of(answer("CurrentMode").packet), 0);
  for (const char* no : {"StartRecording", "TimelinePlay", "SetPlaybackTakeName,x", "NoSuchCommand"}) {
    const Reply r = answer(no);
    EXPECT_EQ(int_of(r.packet), 1) << no;
    EXPECT_TRUE(r.failed) << no;
  }
  // Message ids a server sends, or none at all, are unrecognized requests.
  for (uint16_t id : {static_cast<uint16_t>(kServerInfo), static_cast<uint16_t>(kFrameOfData), uint16_t{77}}) {
    Request r;
    r.ok = true;
    r.id = id;
    EXPECT_EQ(Answer(r, model, &state).packet, Packet(kUnrecognizedRequest, "")) << id;
  }
  Request connect;
  connect.ok = true;
  connect.id = kConnect;
  const Reply info = Answer(connect, model, &state);
  EXPECT_EQ(info.subscription, Subscription::kSubscribe);
  ASSERT_EQ(info.packet.size(), 4u + 256 + 8 + 8 + 2 + 1 + 4);
  EXPECT_EQ(info.packet.substr(4, 9), "mocap-hub");
  EXPECT_EQ(info.packet[4 + 260], 3);  // the version streamed now
  EXPECT_EQ(info.packet[4 + 261], 1);
}

TEST(NatNetModelDef, DescribesBodiesAndTheirMarkers) {
  for (const Version v : {Version{3, 0}, Version{4, 0}, Version{4, 1}}) {
    SCOPED_TRACE(ToString(v));
    Model model = TwoBodies();
    model.label_names = {"head", "hand"};
    const std::string p = EncodeModelDef(model, v);
    Reader r{p};
    EXPECT_EQ(r.Get<uint16_t>(), kModelDef);
    EXPECT_EQ(r.Get<uint16_t>(), p.size() - 4);
    ASSERT_EQ(r.Get<int32_t>(), 5);
    const bool sized = v.major == 4 && v.minor == 1;
    std::vector<std::string> sets;
    for (int i = 0; i < 3; ++i) {
      EXPECT_EQ(r.Get<int32_t>(), 0);
      size_t end = 0;
      if (sized) end = r.Get<int32_t>() + r.at;
      sets.push_back(r.Str());
      const int n = r.Get<int32_t>();
      for (int m = 0; m < n; ++m) sets.back() += " " + r.Str();
      if (sized) {
      EXPECT_EQ(r.at, end);
    }
    }
    EXPECT_EQ(sets, (std::vector<std::string>{"drone Marker1 Marker2 Marker3", "wand Marker1 Marker2 Marker3 Marker4",
                                              "all head hand"}));
    for (int b = 0; b < 2; ++b) {
      EXPECT_EQ(r.Get<int32_t>(), 1);
      size_t end = 0;
      if (sized) end = r.Get<int32_t>() + r.at;
      EXPECT_EQ(r.Str(), model.bodies[b].name);
      EXPECT_EQ(r.Get<int32_t>(), b + 1);
      EXPECT_EQ(r.Get<int32_t>(), -1);
      for (int k = 0; k < 3; ++k) EXPECT_EQ(r.Get<float>(), 0.0f);
      const int n = r.Get<int32_t>();
      ASSERT_EQ(n, static_cast<int>(model.bodies[b].markers.size()));
      for (int m = 0; m < n; ++m) {
        for (int k = 0; k < 3; ++k) {
          EXPECT_FLOAT_EQ(r.Get<float>(), (model.bodies[b].markers[m][k] - model.bodies[b].pivot[k]) * 1e-3);
        }
      }
      for (int m = 0; m < n; ++m) EXPECT_EQ(r.Get<int32_t>(), 0);
      if (v.major >= 4) {
        for (int m = 0; m < n; ++m) EXPECT_EQ(r.Str(), "Marker" + std::to_string(m + 1));
      }
      if (sized) {
      EXPECT_EQ(r.at, end);
    }
    }
    EXPECT_EQ(r.at, p.size());
  }
}

TEST(NatNetFrame, CarriesMarkersBodiesAndStamps) {
  for (const Version v : {Version{3, 1}, Version{4, 0}, Version{4, 1}}) {
    SCOPED_TRACE(ToString(v));
    const Model model = TwoBodies();
    const pipeline::LiveFrame f = OneFrame();
    const std::string p = EncodeFrame(f, model, v, FrameStamps{f.publish_ns + 50'000});
    const bool sized = v.major == 4 && v.minor == 1;
    Reader r{p};
    auto section = [&](int expected) {
      EXPECT_EQ(r.Get<int32_t>(), expected);
      return sized ? r.Get<int32_t>() + r.at : 0;
    };
    EXPECT_EQ(r.Get<uint16_t>(), kFrameOfData);
    EXPECT_EQ(r.Get<uint16_t>(), p.size() - 4);
    EXPECT_EQ(r.Get<int32_t>(), 1234);
    size_t end = section(2);
    // The tracked drone's markers where its pose puts them; the untracked wand's are NaN.
    EXPECT_EQ(r.Str(), "drone");
    ASSERT_EQ(r.Get<int32_t>(), 3);
    for (const Eigen::Vector3d& m : model.bodies[0].markers) {
      const Eigen::Vector3d world = f.bodies[0].position + f.bodies[0].orientation * (m - model.bodies[0].pivot);
      for (int k = 0; k < 3; ++k) EXPECT_NEAR(r.Get<float>(), world[k] * 1e-3, 1e-7);
    }
    EXPECT_EQ(r.Str(), "wand");
    ASSERT_EQ(r.Get<int32_t>(), 4);
    for (int k = 0; k < 12; ++k) EXPECT_TRUE(std::isnan(r.Get<float>()));
    if (sized) {
      EXPECT_EQ(r.at, end);
    }
    end = section(1);  // the point without a confirmed track
    EXPECT_FLOAT_EQ(r.Get<float>(), -0.005f);
    EXPECT_FLOAT_EQ(r.Get<float>(), 0.006f);
    EXPECT_FLOAT_EQ(r.Get<float>(), -0.007f);
    if (sized) {
      EXPECT_EQ(r.at, end);
    }
    end = section(2);
    EXPECT_EQ(r.Get<int32_t>(), 1);
    EXPECT_FLOAT_EQ(r.Get<float>(), 0.1f);
    EXPECT_FLOAT_EQ(r.Get<float>(), 0.2f);
    EXPECT_FLOAT_EQ(r.Get<float>(), 0.3f);
    const Eigen::Quaterniond& q = f.bodies[0].orientation;
    EXPECT_FLOAT_EQ(r.Get<float>(), static_cast<float>(q.x()));
    EXPECT_FLOAT_EQ(r.Get<float>(), static_cast<float>(q.y()));
    EXPECT_FLOAT_EQ(r.Get<float>(), static_cast<float>(q.z()));
    EXPECT_FLOAT_EQ(r.Get<float>(), static_cast<float>(q.w()));
    EXPECT_FLOAT_EQ(r.Get<float>(), 0.00025f);
    EXPECT_EQ(r.Get<int16_t>(), 1);  // tracking valid
    EXPECT_EQ(r.Get<int32_t>(), 2);
    r.at += 8 * 4;
    EXPECT_EQ(r.Get<int16_t>(), 0);  // the wand was not fitted
    if (sized) {
      EXPECT_EQ(r.at, end);
    }
    end = section(0);  // skeletons
    if (sized) section(0);  // assets
    end = section(2);  // labelled markers: every point
    EXPECT_EQ(r.Get<int32_t>(), 9);  // its track's id
    EXPECT_FLOAT_EQ(r.Get<float>(), 1.0f);
    r.at += 8;
    EXPECT_EQ(r.Get<float>(), 0.0f);
    EXPECT_EQ(r.Get<int16_t>(), 0x02);
    EXPECT_EQ(r.Get<float>(), 0.0f);
    EXPECT_EQ(r.Get<int32_t>(), 0);
    r.at += 16;
    EXPECT_EQ(r.Get<int16_t>(), 0x12);  // unlabelled
    r.at += 4;
    if (sized) {
      EXPECT_EQ(r.at, end);
    }
    section(0);  // force plates
    section(0);  // devices
    EXPECT_EQ(r.Get<uint32_t>(), 0u);
    EXPECT_EQ(r.Get<uint32_t>(), 0u);
    EXPECT_DOUBLE_EQ(r.Get<double>(), 1234.0 / 240.0);
    EXPECT_EQ(r.Get<uint64_t>(), f.trigger_time_ns);
    EXPECT_EQ(r.Get<uint64_t>(), f.last_receive_ns);
    EXPECT_EQ(r.Get<uint64_t>(), f.publish_ns + 50'000);
    if (v.major >= 4) r.at += 8;
    EXPECT_EQ(r.Get<int16_t>(), 0);
    EXPECT_EQ(r.Get<int32_t>(), 0);
    EXPECT_EQ(r.at, p.size());
  }
}

std::shared_ptr<const pipeline::LiveSkeletonModel> TwoBones() {
  auto m = std::make_shared<pipeline::LiveSkeletonModel>();
  m->name = "anna";
  m->bones = {"Hips", "LeftUpLeg"};
  m->parents = {-1, 0};
  m->offsets = {{0, 0, 0}, {90, -60, 0}};
  return m;
}

TEST(NatNetSkeleton, DescribedAfterTheBodiesAndSentSolvedOrInvalid) {
  for (const Version v : {Version{3, 0}, Version{4, 1}}) {
    SCOPED_TRACE(ToString(v));
    const bool sized = v.major == 4 && v.minor == 1;
    Model model = TwoBodies();
    model.skeletons = {TwoBones()};
    const std::string d = EncodeModelDef(model, v);
    Reader r{d};
    r.at = 4;
    ASSERT_EQ(r.Get<int32_t>(), 5);  // 2 markersets, 2 rigid bodies, 1 skeleton
    // Skip to the skeleton: the last dataset.
    for (int i = 0; i < 4; ++i) {
      const int32_t type = r.Get<int32_t>();
      ASSERT_TRUE(type == 0 || type == 1);
      if (sized) {
        r.at += static_cast<size_t>(r.Get<int32_t>());
        continue;
      }
      r.Str();
      if (type == 0) {
        const int n = r.Get<int32_t>();
        for (int m = 0; m < n; ++m) r.Str();
      } else {
        r.at += 4 + 4 + 12;
        const int n = r.Get<int32_t>();
        r.at += static_cast<size_t>(n) * 16;
        if (v.major >= 4)
          for (int m = 0; m < n; ++m) r.Str();
      }
    }
    EXPECT_EQ(r.Get<int32_t>(), 2);
    size_t end = sized ? r.Get<int32_t>() + r.at : 0;
    EXPECT_EQ(r.Str(), "anna");
    EXPECT_EQ(r.Get<int32_t>(), 3);  // after the two bodies' IDs
    ASSERT_EQ(r.Get<int32_t>(), 2);
    EXPECT_EQ(r.Str(), "Hips");
    EXPECT_EQ(r.Get<int32_t>(), 1);
    EXPECT_EQ(r.Get<int32_t>(), 0);  // the root
    r.at += 12;
    EXPECT_EQ(r.Get<int32_t>(), 0);  // no markers
    EXPECT_EQ(r.Str(), "LeftUpLeg");
    EXPECT_EQ(r.Get<int32_t>(), 2);
    EXPECT_EQ(r.Get<int32_t>(), 1);
    EXPECT_FLOAT_EQ(r.Get<float>(), 0.09f);
    EXPECT_FLOAT_EQ(r.Get<float>(), -0.06f);
    EXPECT_FLOAT_EQ(r.Get<float>(), 0.0f);
    EXPECT_EQ(r.Get<int32_t>(), 0);
    if (sized) {
      EXPECT_EQ(r.at, end);
    }
    EXPECT_EQ(r.at, d.size());

    // Frames: solved, then not.
    for (const bool solved : {true, false}) {
      SCOPED_TRACE(solved);
      pipeline::LiveFrame f = OneFrame();
      f.points.clear();
      pipeline::LiveSkeleton s;
      s.model = model.skeletons[0];
      s.solved = solved;
      s.rms_mm = 4.0;
      if (solved) {
        s.bones.resize(2);
        s.bones[1].position = {90, 940, 0};
        s.bones[1].orientation = Eigen::Quaterniond(Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitX()));
      }
      f.skeletons = {s};
      const std::string p = EncodeFrame(f, model, v, FrameStamps{});
      Reader fr{p};
      fr.at = 8;
      auto section = [&](int expected) {
        EXPECT_EQ(fr.Get<int32_t>(), expected);
        return sized ? fr.Get<int32_t>() + fr.at : 0;
      };
      if (!sized) continue;  // frames read by section sizes (4.1); the older layouts by the SDK's client
      fr.at = section(2);  // markersets
      fr.at = section(0);  // others
      fr.at = section(2);  // rigid bodies
      end = section(1);
      EXPECT_EQ(fr.Get<int32_t>(), 3);
      ASSERT_EQ(fr.Get<int32_t>(), 2);
      for (int b = 0; b < 2; ++b) {
        EXPECT_EQ(fr.Get<int32_t>(), (3 << 16) | (b + 1));
        const float x = fr.Get<float>();
        const float y = fr.Get<float>();
        fr.Get<float>();
        const float qx = fr.Get<float>();
        fr.at += 8;
        const float qw = fr.Get<float>();
        const float error = fr.Get<float>();
        const int16_t params = fr.Get<int16_t>();
        if (solved) {
          EXPECT_FLOAT_EQ(x, b ? 0.09f : 0.0f);
          EXPECT_FLOAT_EQ(y, b ? 0.94f : 0.0f);
          EXPECT_NEAR(qx, b ? std::sin(0.25) : 0.0, 1e-6);
          EXPECT_NEAR(qw, b ? std::cos(0.25) : 1.0, 1e-6);
          EXPECT_FLOAT_EQ(error, 0.004f);
          EXPECT_EQ(params, 1);
        } else {
          EXPECT_TRUE(std::isnan(x) && std::isnan(qw));
          EXPECT_EQ(params, 0);  // not tracked: no stale pose
        }
      }
      EXPECT_EQ(fr.at, end);
    }
  }
}

TEST(NatNetFrame, ManyPointsAreCutToOneDatagram) {
  pipeline::LiveFrame f;
  f.points.resize(5000);
  uint64_t dropped = 0;
  const std::string p = EncodeFrame(f, Model{}, Version{}, FrameStamps{}, &dropped);
  EXPECT_LE(p.size(), kMaxPacket);
  EXPECT_GT(dropped, 0u);
  EXPECT_LT(dropped, 5000u);
  uint16_t declared = 0;
  std::memcpy(&declared, p.data() + 2, 2);
  EXPECT_EQ(declared, p.size() - 4);
}

}  // namespace
}  // namespace mocap::stream::natnet

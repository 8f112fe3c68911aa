// The stream's messages: every field of a frame survives libprotobuf's own parse, parts leave
// out what was not asked for, the size limit drops points (counted) instead of overflowing a
// datagram, and requests are decoded or refused with a reason.
#include "stream/stream_encoding.h"

#include <gtest/gtest.h>

#include "mocap_stream.pb.h"

namespace mocap::stream {
namespace {

pipeline::LiveFrame Frame(size_t points) {
  pipeline::LiveFrame f;
  f.frame_number = 1234567;
  f.trigger_time_ns = 1'800'000'000'123'456'789ull;
  f.publish_ns = f.trigger_time_ns + 2'500'000;
  f.cameras = 8;
  for (size_t i = 0; i < points; ++i) {
    pipeline::LivePoint p;
    p.position = {100.0 + static_cast<double>(i), -200.5, 1500.25};
    p.rms_px = 0.25;
    p.views = 3 + static_cast<int>(i % 4);
    p.id = 900 + i;
    if (i % 3 != 0) p.marker = static_cast<int>(i);  // confirmed column i, else provisional
    f.points.push_back(p);
  }
  pipeline::LiveBody body;
  body.id = 1;
  body.name = "wand";
  body.tracked = true;
  body.position = {1.0, 2.0, 3.0};
  body.orientation = Eigen::Quaterniond(Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitZ()));
  body.mean_error_mm = 0.3;
  f.bodies.push_back(body);
  pipeline::LiveBody lost;
  lost.id = 2;
  lost.name = "drone";
  f.bodies.push_back(lost);
  return f;
}

v1::StreamFrame Parse(const EncodedFrame& e) {
  v1::StreamFrame out;
  EXPECT_TRUE(out.ParseFromString(e.bytes));
  return out;
}

TEST(StreamEncoding, EveryFieldSurvivesTheRoundTrip) {
  const pipeline::LiveFrame f = Frame(7);
  const v1::StreamFrame m = Parse(EncodeStreamFrame(f, kPartPoints | kPartBodies));
  EXPECT_EQ(m.frame_number(), f.frame_number);
  EXPECT_EQ(m.trigger_time_ns(), f.trigger_time_ns);
  EXPECT_EQ(m.publish_time_ns(), f.publish_ns);
  EXPECT_EQ(m.cameras(), 8u);
  EXPECT_EQ(m.parts(), kPartPoints | kPartBodies);
  ASSERT_EQ(m.points_size(), 7);
  for (int i = 0; i < 7; ++i) {
    const v1::Point& p = m.points(i);
    EXPECT_FLOAT_EQ(p.x(), 100.0f + static_cast<float>(i));
    EXPECT_FLOAT_EQ(p.y(), -200.5f);
    EXPECT_FLOAT_EQ(p.z(), 1500.25f);
    EXPECT_FLOAT_EQ(p.residual_px(), 0.25f);
    EXPECT_EQ(p.views(), static_cast<uint32_t>(3 + i % 4));
    EXPECT_EQ(p.id(), 900u + static_cast<uint64_t>(i));  // provisional or confirmed
    if (i % 3 == 0) {
      EXPECT_EQ(p.marker(), 0);
      EXPECT_EQ(p.provisional_track(), 900u + static_cast<uint64_t>(i));
    } else {
      EXPECT_EQ(p.marker(), i + 1);  // 1-based, as the TRC's M001
      EXPECT_EQ(p.provisional_track(), 0u);
    }
  }
  ASSERT_EQ(m.bodies_size(), 2);
  EXPECT_EQ(m.bodies(0).name(), "wand");
  EXPECT_TRUE(m.bodies(0).tracked());
  EXPECT_FLOAT_EQ(m.bodies(0).z(), 3.0f);
  EXPECT_NEAR(m.bodies(0).qz(), std::sin(0.25), 1e-6);
  EXPECT_NEAR(m.bodies(0).qw(), std::cos(0.25), 1e-6);
  EXPECT_FALSE(m.bodies(1).tracked());
  EXPECT_EQ(m.bodies(1).qw(), 0.0f);
  EXPECT_EQ(m.points_dropped(), 0u);
}

TEST(StreamEncoding, NamesOnlyWithTheLabelsPart) {
  pipeline::LiveFrame f = Frame(3);
  f.label_names = std::make_shared<const std::vector<std::string>>(std::vector<std::string>{"R.ASIS", "Head"});
  f.points[1].label = 1;
  f.points[2].label = 0;
  const v1::StreamFrame named = Parse(EncodeStreamFrame(f, kPartPoints | kPartLabels));
  ASSERT_EQ(named.points_size(), 3);
  EXPECT_EQ(named.points(0).label(), "");
  EXPECT_EQ(named.points(1).label(), "Head");
  EXPECT_EQ(named.points(2).label(), "R.ASIS");
  const v1::StreamFrame plain = Parse(EncodeStreamFrame(f, kPartPoints));
  EXPECT_EQ(plain.points(1).label(), "");
}

TEST(StreamEncoding, OnlyThePartsAskedFor) {
  const pipeline::LiveFrame f = Frame(5);
  const v1::StreamFrame points = Parse(EncodeStreamFrame(f, kPartPoints));
  EXPECT_EQ(points.points_size(), 5);
  EXPECT_EQ(points.bodies_size(), 0);
  const v1::StreamFrame bodies = Parse(EncodeStreamFrame(f, kPartBodies));
  EXPECT_EQ(bodies.points_size(), 0);
  EXPECT_EQ(bodies.bodies_size(), 2);
  EXPECT_EQ(bodies.frame_number(), f.frame_number);
}

TEST(StreamEncoding, BonesOnlyWithTheBonesPartAndOnlyWhenSolved) {
  pipeline::LiveFrame f = Frame(2);
  auto model = std::make_shared<pipeline::LiveSkeletonModel>();
  model->name = "anna";
  model->bones = {"Hips", "LeftUpLeg"};
  model->parents = {-1, 0};
  pipeline::LiveSkeleton solved;
  solved.model = model;
  solved.solved = true;
  solved.state = "solved";
  solved.markers = 30;
  solved.rms_mm = 4.5;
  solved.max_mm = 12.25;
  solved.bones.resize(2);
  solved.bones[1].position = {90.0, 900.0, -15.5};
  solved.bones[1].orientation = Eigen::Quaterniond(Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitX()));
  pipeline::LiveSkeleton lost;
  lost.model = model;
  lost.state = "too few markers";
  lost.markers = 2;
  f.skeletons = {solved, lost};
  const v1::StreamFrame m = Parse(EncodeStreamFrame(f, kPartBones));
  EXPECT_EQ(m.points_size(), 0);
  ASSERT_EQ(m.skeletons_size(), 2);
  const v1::Skeleton& s = m.skeletons(0);
  EXPECT_EQ(s.name(), "anna");
  EXPECT_TRUE(s.solved());
  EXPECT_EQ(s.state(), "solved");
  EXPECT_EQ(s.markers(), 30u);
  EXPECT_FLOAT_EQ(s.rms_mm(), 4.5f);
  EXPECT_FLOAT_EQ(s.max_mm(), 12.25f);
  ASSERT_EQ(s.bones_size(), 2);
  EXPECT_EQ(s.bones(0).name(), "Hips");
  EXPECT_EQ(s.bones(0).parent(), -1);
  EXPECT_EQ(s.bones(1).name(), "LeftUpLeg");
  EXPECT_EQ(s.bones(1).parent(), 0);
  EXPECT_FLOAT_EQ(s.bones(1).z(), -15.5f);
  EXPECT_NEAR(s.bones(1).qx(), std::sin(0.25), 1e-6);
  EXPECT_NEAR(s.bones(1).qw(), std::cos(0.25), 1e-6);
  EXPECT_FALSE(m.skeletons(1).solved());
  EXPECT_EQ(m.skeletons(1).state(), "too few markers");
  EXPECT_EQ(m.skeletons(1).bones_size(), 0);
  EXPECT_EQ(Parse(EncodeStreamFrame(f, kPartPoints | kPartBodies)).skeletons_size(), 0);
}

TEST(StreamEncoding, PointsBeyondTheLimitAreDroppedAndCounted) {
  const pipeline::LiveFrame f = Frame(4000);
  const EncodedFrame whole = EncodeStreamFrame(f, kPartPoints, 1'000'000);
  EXPECT_EQ(whole.points_dropped, 0u);
  EXPECT_GT(whole.bytes.size(), kMaxStreamMessage);
  const EncodedFrame capped = EncodeStreamFrame(f, kPartPoints | kPartBodies);
  EXPECT_LE(capped.bytes.size(), kMaxStreamMessage);
  const v1::StreamFrame m = Parse(capped);
  EXPECT_GT(m.points_size(), 1000);
  EXPECT_EQ(static_cast<size_t>(m.points_size()) + m.points_dropped(), f.points.size());
  EXPECT_EQ(capped.points_dropped, m.points_dropped());
  EXPECT_EQ(m.bodies_size(), 2);
  // Tight limits never overshoot either.
  for (size_t limit : {64u, 200u, 1000u, 5000u}) EXPECT_LE(EncodeStreamFrame(f, kPartPoints, limit).bytes.size(), limit);
}

TEST(StreamEncoding, RequestsDecodedOrRefusedWithAReason) {
  auto decode = [](const std::string& bytes) {
    return DecodeStreamRequest(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size());
  };
  StreamRequest r = decode(EncodeSubscribe(kPartBodies));
  ASSERT_TRUE(r.ok) << r.reason;
  EXPECT_TRUE(r.subscribe);
  EXPECT_EQ(r.parts, kPartBodies);
  r = decode(EncodeSubscribe(0));
  ASSERT_TRUE(r.ok);
  EXPECT_EQ(r.parts, kDefaultParts);
  r = decode(EncodeUnsubscribe());
  ASSERT_TRUE(r.ok);
  EXPECT_FALSE(r.subscribe);

  v1::StreamRequest future;
  future.set_version(2);
  future.mutable_subscribe();
  r = decode(future.SerializeAsString());
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.reason.find("version 2"), std::string::npos) << r.reason;
  r = decode(EncodeSubscribe(kPartBones));
  ASSERT_TRUE(r.ok) << r.reason;
  EXPECT_EQ(r.parts, kPartBones);
  r = decode(EncodeSubscribe(64));
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.reason.find("unknown part"), std::string::npos) << r.reason;
  v1::StreamRequest empty;
  empty.set_version(1);
  EXPECT_FALSE(decode(empty.SerializeAsString()).ok);
  EXPECT_FALSE(decode(std::string("\xff\xff\xff", 3)).ok);
  r = decode(std::string(100, '\0'));
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.reason.find("100 bytes"), std::string::npos);
  EXPECT_FALSE(DecodeStreamRequest(nullptr, 0).ok);
}

TEST(StreamEncoding, PartLists) {
  EXPECT_EQ(ParseParts("points"), kPartPoints);
  EXPECT_EQ(ParseParts("bodies,points,labels,bones"), kAllParts);
  EXPECT_EQ(ParseParts("bones"), kPartBones);
  EXPECT_THROW(ParseParts("points,skeletons"), std::invalid_argument);
  EXPECT_THROW(ParseParts(""), std::invalid_argument);
}

}  // namespace
}  // namespace mocap::stream

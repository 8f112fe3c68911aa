// The C client (clients/c, nanopb) reads what the hub (libprotobuf) writes: two independent
// protobuf runtimes agree on every field, and the client's arrays are never overrun.
#include <gtest/gtest.h>

#include "mocap_stream_client.h"
#include "stream/stream_encoding.h"

namespace mocap::stream {
namespace {

pipeline::LiveFrame Frame(size_t points) {
  pipeline::LiveFrame f;
  f.frame_number = 4242;
  f.trigger_time_ns = 1'800'000'000'000'000'001ull;
  f.publish_ns = f.trigger_time_ns + 900'000;
  f.cameras = 16;
  for (size_t i = 0; i < points; ++i) {
    pipeline::LivePoint p;
    p.position = {static_cast<double>(i), -5.5, 1000.0};
    p.rms_px = 0.125;
    p.views = 4;
    p.id = 70 + i;
    if (i % 2) p.marker = static_cast<int>(i);
    f.points.push_back(p);
  }
  pipeline::LiveBody body;
  body.id = 3;
  body.name = "drone";
  body.tracked = true;
  body.position = {10.0, 20.0, 30.0};
  body.mean_error_mm = 0.25;
  f.bodies.push_back(body);
  return f;
}

mocap_stream_frame Decode(const EncodedFrame& e, mocap_stream_point* points, size_t np, mocap_stream_body* bodies,
                          size_t nb) {
  mocap_stream_frame frame{};
  frame.points = points;
  frame.point_capacity = np;
  frame.bodies = bodies;
  frame.body_capacity = nb;
  EXPECT_EQ(mocap_stream_decode(reinterpret_cast<const uint8_t*>(e.bytes.data()), e.bytes.size(), &frame), 0);
  return frame;
}

TEST(CClient, ReadsEveryFieldTheHubWrites) {
  mocap_stream_point points[8];
  mocap_stream_body bodies[2];
  const mocap_stream_frame f = Decode(EncodeStreamFrame(Frame(6), kPartPoints | kPartBodies), points, 8, bodies, 2);
  EXPECT_EQ(f.frame_number, 4242u);
  EXPECT_EQ(f.trigger_time_ns, 1'800'000'000'000'000'001ull);
  EXPECT_EQ(f.publish_time_ns, f.trigger_time_ns + 900'000);
  EXPECT_EQ(f.cameras, 16u);
  EXPECT_EQ(f.parts, kPartPoints | kPartBodies);
  ASSERT_EQ(f.point_count, 6u);
  EXPECT_EQ(f.points_total, 6u);
  for (size_t i = 0; i < 6; ++i) {
    EXPECT_FLOAT_EQ(points[i].x, static_cast<float>(i));
    EXPECT_FLOAT_EQ(points[i].y, -5.5f);
    EXPECT_FLOAT_EQ(points[i].residual_px, 0.125f);
    EXPECT_EQ(points[i].views, 4u);
    EXPECT_EQ(points[i].marker, i % 2 ? static_cast<int32_t>(i) + 1 : 0);
    EXPECT_EQ(points[i].provisional_track, i % 2 ? 0u : 70u + i);
    EXPECT_EQ(points[i].id, 70u + i);
    EXPECT_STREQ(points[i].label, "");
  }
  ASSERT_EQ(f.body_count, 1u);
  EXPECT_EQ(bodies[0].id, 3u);
  EXPECT_STREQ(bodies[0].name, "drone");
  EXPECT_TRUE(bodies[0].tracked);
  EXPECT_FLOAT_EQ(bodies[0].z, 30.0f);
  EXPECT_FLOAT_EQ(bodies[0].qw, 1.0f);
  EXPECT_FLOAT_EQ(bodies[0].mean_error_mm, 0.25f);
}

TEST(CClient, FillsNoMoreThanTheCallersArrays) {
  mocap_stream_point points[3];
  const mocap_stream_frame f = Decode(EncodeStreamFrame(Frame(50), kPartPoints | kPartBodies), points, 3, nullptr, 0);
  EXPECT_EQ(f.point_count, 3u);
  EXPECT_EQ(f.points_total, 50u);
  EXPECT_EQ(f.body_count, 0u);
  EXPECT_EQ(f.bodies_total, 1u);
}

TEST(CClient, RefusesWhatIsNoFrame) {
  mocap_stream_frame frame{};
  const uint8_t garbage[] = {0x0a, 0xff, 0xff, 0xff, 0xff, 0x0f, 0x01};
  EXPECT_NE(mocap_stream_decode(garbage, sizeof garbage, &frame), 0);
}

}  // namespace
}  // namespace mocap::stream

// Datagram validation and encoding rules of protocol v1.
#include "wire/packet.h"

#include <gtest/gtest.h>

#include "wire/chunking.h"
#include "wire/limits.h"

namespace mocap::wire {
namespace {

v1::MarkerFrame FrameWithMarkers(uint32_t n) {
  v1::MarkerFrame f;
  f.set_node_id(3);
  f.set_frame_number(1234567);
  f.set_width(1280);
  f.set_height(800);
  for (uint32_t i = 0; i < n; ++i) {
    v1::Marker* m = f.add_markers();
    m->set_x_q8(ToSubpixel(1279.99 - i * 3.3));
    m->set_y_q8(ToSubpixel(799.99 - i * 2.1));
    m->set_area(kMaxBlobArea);
    m->set_peak(kMaxBrightness);
    m->set_mean(kMaxBrightness);
    m->set_flags(kMarkerFlagsMask);
  }
  return f;
}

TEST(Packet, WorstCaseChunksStayUnderDatagramLimit) {
  v1::MarkerFrame f = FrameWithMarkers(256);
  f.set_trigger_time_ns(~0ull);
  f.set_capture_time_ns(~0ull);
  f.set_send_time_ns(~0ull);
  f.set_exposure_us(~0u);
  f.set_flags(kFrameFlagsMask);
  f.set_node_id(~0u);
  f.set_frame_number(~0ull);
  const auto packets = SplitMarkerFrame(f);
  ASSERT_EQ(packets.size(), 6u);
  for (const auto& p : packets) {
    const auto bytes = Encode(p);
    EXPECT_LE(bytes.size(), kMaxPacketBytes);
    const DecodeResult back = Decode(bytes.data(), bytes.size());
    EXPECT_TRUE(back.ok) << back.reason;
  }
}

TEST(Packet, SubpixelPrecisionIsBetterThanOneSixtyFourth) {
  for (double x = 0.0; x < 1280.0; x += 0.37) {
    EXPECT_LE(std::abs(FromSubpixel(ToSubpixel(x)) - x), 1.0 / 512.0 + 1e-12);
  }
}

TEST(Packet, RejectsWrongVersion) {
  v1::Packet p = SplitMarkerFrame(FrameWithMarkers(2))[0];
  p.set_version(2);
  std::string bytes = p.SerializeAsString();
  const DecodeResult r = Decode(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size());
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.reason.find("version"), std::string::npos);
}

TEST(Packet, RejectsOversizedAndEmptyAndGarbage) {
  std::vector<uint8_t> big(kMaxPacketBytes + 1, 0);
  EXPECT_FALSE(Decode(big.data(), big.size()).ok);
  EXPECT_FALSE(Decode(big.data(), 0).ok);
  const uint8_t garbage[] = {0xff, 0xff, 0xff, 0xff, 0x0f};
  const DecodeResult r = Decode(garbage, sizeof garbage);
  EXPECT_FALSE(r.ok);
  EXPECT_FALSE(r.reason.empty());
}

TEST(Packet, RejectsTruncatedDatagram) {
  const auto bytes = Encode(SplitMarkerFrame(FrameWithMarkers(10))[0]);
  for (size_t cut = 1; cut < bytes.size(); ++cut) {
    EXPECT_FALSE(Decode(bytes.data(), cut).ok) << "accepted a datagram cut at " << cut;
  }
}

TEST(Packet, RejectsMarkerOutsideImageAndBadChunkFields) {
  v1::Packet p = SplitMarkerFrame(FrameWithMarkers(1))[0];
  p.mutable_marker_frame()->mutable_markers(0)->set_x_q8(1280 * 256);
  EXPECT_NE(Validate(p), "");
  p = SplitMarkerFrame(FrameWithMarkers(60))[1];
  p.mutable_marker_frame()->set_first_marker(0);
  EXPECT_NE(Validate(p), "");
  p = SplitMarkerFrame(FrameWithMarkers(60))[1];
  p.mutable_marker_frame()->set_chunk_count(5);
  EXPECT_NE(Validate(p), "");
  p = SplitMarkerFrame(FrameWithMarkers(60))[0];
  p.mutable_marker_frame()->mutable_markers(0)->set_mean(kMaxBrightness + 1);
  EXPECT_NE(Validate(p), "");
}

TEST(Packet, EncodeRefusesInvalidPackets) {
  v1::Packet p;
  p.set_version(1);
  EXPECT_THROW(Encode(p), std::invalid_argument);
  p.mutable_control()->mutable_preview_request()->set_downscale(3);
  EXPECT_THROW(Encode(p), std::invalid_argument);
  p.mutable_control()->mutable_preview_request()->set_downscale(4);
  EXPECT_NO_THROW(Encode(p));
}

TEST(Packet, PictureControlRules) {
  v1::Packet p;
  p.set_version(1);
  auto* picture = p.mutable_control()->mutable_set_picture();
  EXPECT_EQ(Validate(p), "control: picture command changes nothing");
  picture->set_contrast_pct(101);  // not flagged: ignored, still nothing to change
  picture->set_set_brightness(true);
  picture->set_brightness_pct(0);
  EXPECT_EQ(Validate(p), "");
  picture->set_set_contrast(true);
  EXPECT_EQ(Validate(p), "control: picture control outside 0..100 %");
  picture->set_contrast_pct(100);
  EXPECT_EQ(Validate(p), "");
}

TEST(Packet, ControlAndPreviewRules) {
  v1::Packet p;
  p.set_version(1);
  auto* mask = p.mutable_control()->mutable_set_mask();
  mask->set_cell_px(8);
  mask->set_cells_x(160);
  mask->set_cells_y(100);
  mask->set_chunk_count(3);
  mask->set_chunk_index(2);
  mask->set_bit_offset(2 * 896 * 8);
  mask->set_bits(std::string(16000 / 8 - 2 * 896, '\x01'));
  EXPECT_EQ(Validate(p), "");
  mask->set_bit_offset(2 * 896 * 8 + 8);
  EXPECT_NE(Validate(p), "");

  v1::Packet q;
  q.set_version(1);
  auto* pc = q.mutable_preview_chunk();
  pc->set_node_id(1);
  pc->set_width(160);
  pc->set_height(100);
  pc->set_chunk_count(14);
  pc->set_chunk_index(13);
  pc->set_offset(16000 - 400);
  pc->set_data(std::string(400, 'a'));
  EXPECT_EQ(Validate(q), "");
  pc->set_offset(16000 - 399);
  EXPECT_NE(Validate(q), "");
}

TEST(Packet, ControlAckRules) {
  v1::Packet p;
  p.set_version(1);
  auto* ack = p.mutable_control_ack();
  ack->set_node_id(4);
  ack->set_sequence(99);
  ack->set_result(v1::CONTROL_RESULT_APPLIED);
  EXPECT_EQ(Validate(p), "");
  ack->set_reason("done");
  EXPECT_EQ(Validate(p), "control ack: applied with a reason");
  ack->set_result(v1::CONTROL_RESULT_IGNORED);
  EXPECT_EQ(Validate(p), "");
  ack->set_result(v1::CONTROL_RESULT_REJECTED);
  ack->set_reason(std::string(kMaxAckReasonBytes, 'r'));
  EXPECT_EQ(Validate(p), "");
  const auto bytes = Encode(p);
  const DecodeResult back = Decode(bytes.data(), bytes.size());
  ASSERT_TRUE(back.ok) << back.reason;
  EXPECT_EQ(back.packet.control_ack().reason(), ack->reason());
  ack->set_reason(std::string(kMaxAckReasonBytes + 1, 'r'));
  EXPECT_EQ(Validate(p), "control ack: reason too long");
  ack->clear_reason();
  EXPECT_EQ(Validate(p), "control ack: rejected without a reason");
  ack->set_reason("x");
  ack->set_result(static_cast<v1::ControlResult>(7));
  EXPECT_EQ(Validate(p), "control ack: unknown result");
  ack->set_result(v1::CONTROL_RESULT_REJECTED);
  ack->set_node_id(0);
  EXPECT_EQ(Validate(p), "control ack: node_id 0");
}

}  // namespace
}  // namespace mocap::wire

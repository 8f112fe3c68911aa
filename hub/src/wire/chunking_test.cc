// Chunk split and exact reassembly, including loss, duplicates and disagreeing chunks.
#include "wire/chunking.h"

#include <algorithm>
#include <random>

#include <gtest/gtest.h>

#include "wire/limits.h"
#include "wire/packet.h"

namespace mocap::wire {
namespace {

v1::MarkerFrame Frame(uint32_t node, uint64_t number, uint32_t n) {
  v1::MarkerFrame f;
  f.set_node_id(node);
  f.set_frame_number(number);
  f.set_width(1280);
  f.set_height(800);
  f.set_capture_time_ns(number * 1000);
  for (uint32_t i = 0; i < n; ++i) {
    v1::Marker* m = f.add_markers();
    m->set_x_q8(i * 97 + 5);
    m->set_y_q8(i * 31 + 7);
    m->set_area(i + 1);
    m->set_peak(200);
    m->set_mean(150);
  }
  return f;
}

TEST(Chunking, TwoHundredFiftySixMarkersReassembleExactlyInAnyOrder) {
  const v1::MarkerFrame original = Frame(2, 77, 256);
  auto packets = SplitMarkerFrame(original);
  ASSERT_EQ(packets.size(), 6u);
  std::mt19937 rng(5);
  std::shuffle(packets.begin(), packets.end(), rng);
  ChunkAssembler assembler;
  v1::MarkerFrame out;
  for (size_t i = 0; i < packets.size(); ++i) {
    const auto bytes = Encode(packets[i]);
    const DecodeResult decoded = Decode(bytes.data(), bytes.size());
    ASSERT_TRUE(decoded.ok) << decoded.reason;
    const auto outcome = assembler.Add(decoded.packet.marker_frame(), &out);
    EXPECT_EQ(outcome, i + 1 == packets.size() ? ChunkAssembler::Outcome::kComplete
                                               : ChunkAssembler::Outcome::kIncomplete);
  }
  ASSERT_EQ(out.markers_size(), 256);
  for (int i = 0; i < 256; ++i) {
    EXPECT_EQ(out.markers(i).x_q8(), original.markers(i).x_q8());
    EXPECT_EQ(out.markers(i).area(), original.markers(i).area());
  }
  EXPECT_EQ(assembler.pending(), 0u);
}

TEST(Chunking, EmptyFrameIsOneChunk) {
  const auto packets = SplitMarkerFrame(Frame(1, 5, 0));
  ASSERT_EQ(packets.size(), 1u);
  EXPECT_EQ(Validate(packets[0]), "");
  ChunkAssembler assembler;
  v1::MarkerFrame out;
  EXPECT_EQ(assembler.Add(packets[0].marker_frame(), &out), ChunkAssembler::Outcome::kComplete);
  EXPECT_EQ(out.markers_size(), 0);
}

TEST(Chunking, DuplicateChunkIsDroppedAndInconsistentChunkRejected) {
  auto packets = SplitMarkerFrame(Frame(1, 9, 100));
  ChunkAssembler assembler;
  v1::MarkerFrame out;
  EXPECT_EQ(assembler.Add(packets[0].marker_frame(), &out), ChunkAssembler::Outcome::kIncomplete);
  EXPECT_EQ(assembler.Add(packets[0].marker_frame(), &out), ChunkAssembler::Outcome::kDuplicate);
  v1::MarkerFrame liar = packets[1].marker_frame();
  liar.set_capture_time_ns(1);
  EXPECT_EQ(assembler.Add(liar, &out), ChunkAssembler::Outcome::kInconsistent);
  EXPECT_EQ(assembler.Add(packets[1].marker_frame(), &out), ChunkAssembler::Outcome::kIncomplete);
  EXPECT_EQ(assembler.Add(packets[2].marker_frame(), &out), ChunkAssembler::Outcome::kComplete);
  EXPECT_EQ(out.markers_size(), 100);
}

TEST(Chunking, ChunkResentAfterCompletionIsADuplicate) {
  auto packets = SplitMarkerFrame(Frame(1, 9, 60));
  ChunkAssembler assembler;
  v1::MarkerFrame out;
  EXPECT_EQ(assembler.Add(packets[0].marker_frame(), &out), ChunkAssembler::Outcome::kIncomplete);
  EXPECT_EQ(assembler.Add(packets[1].marker_frame(), &out), ChunkAssembler::Outcome::kComplete);
  EXPECT_EQ(assembler.Add(packets[0].marker_frame(), &out), ChunkAssembler::Outcome::kDuplicate);
  EXPECT_EQ(assembler.pending(), 0u);
  auto single = SplitMarkerFrame(Frame(1, 10, 3));
  EXPECT_EQ(assembler.Add(single[0].marker_frame(), &out), ChunkAssembler::Outcome::kComplete);
  EXPECT_EQ(assembler.Add(single[0].marker_frame(), &out), ChunkAssembler::Outcome::kDuplicate);
}

TEST(Chunking, LostChunkLeavesPartialUntilDiscarded) {
  ChunkAssembler assembler(4);
  v1::MarkerFrame out;
  for (uint64_t n = 0; n < 6; ++n) {
    auto packets = SplitMarkerFrame(Frame(1, n, 50));
    const auto outcome = assembler.Add(packets[0].marker_frame(), &out);
    EXPECT_EQ(outcome, n < 4 ? ChunkAssembler::Outcome::kIncomplete : ChunkAssembler::Outcome::kOverflow);
  }
  EXPECT_EQ(assembler.pending(), 4u);
  EXPECT_EQ(assembler.DiscardBefore(5), 3u);
  EXPECT_EQ(assembler.pending(), 1u);
}

TEST(Chunking, SameFrameNumberFromTwoNodesStaysApart) {
  ChunkAssembler assembler;
  v1::MarkerFrame out;
  auto a = SplitMarkerFrame(Frame(1, 3, 60));
  auto b = SplitMarkerFrame(Frame(2, 3, 70));
  EXPECT_EQ(assembler.Add(a[0].marker_frame(), &out), ChunkAssembler::Outcome::kIncomplete);
  EXPECT_EQ(assembler.Add(b[1].marker_frame(), &out), ChunkAssembler::Outcome::kIncomplete);
  EXPECT_EQ(assembler.Add(a[1].marker_frame(), &out), ChunkAssembler::Outcome::kComplete);
  EXPECT_EQ(out.node_id(), 1u);
  EXPECT_EQ(out.markers_size(), 60);
}

}  // namespace
}  // namespace mocap::wire

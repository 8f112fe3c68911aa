// Preview assembly: whole images from chunks in any order, duplicates, newer frames replacing
// incomplete ones, chunks that do not tile the image, size limits, staleness, and the PNG's
// pixels read back.
#include "service/preview_assembler.h"

#include <algorithm>
#include <random>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include "wire/packet.h"

namespace mocap::service {
namespace {

std::vector<uint8_t> Pattern(uint32_t w, uint32_t h, uint32_t seed) {
  std::vector<uint8_t> pixels(size_t{w} * h);
  for (size_t i = 0; i < pixels.size(); ++i) pixels[i] = static_cast<uint8_t>(i * 7 + seed + (i / w) * 13);
  return pixels;
}

// The image cut as a node would, chunk_bytes per chunk.
std::vector<v1::PreviewChunk> Chunks(uint32_t node, uint64_t frame, uint32_t w, uint32_t h,
                                     const std::vector<uint8_t>& pixels, size_t chunk_bytes = 1152) {
  const uint32_t count = static_cast<uint32_t>((pixels.size() + chunk_bytes - 1) / chunk_bytes);
  std::vector<v1::PreviewChunk> out;
  for (uint32_t i = 0; i < count; ++i) {
    v1::PreviewChunk c;
    c.set_node_id(node);
    c.set_frame_number(frame);
    c.set_mode(v1::PREVIEW_MODE_RAW);
    c.set_width(w);
    c.set_height(h);
    c.set_chunk_index(i);
    c.set_chunk_count(count);
    c.set_offset(static_cast<uint32_t>(i * chunk_bytes));
    const size_t n = std::min(chunk_bytes, pixels.size() - i * chunk_bytes);
    c.set_data(std::string(pixels.begin() + static_cast<std::ptrdiff_t>(i * chunk_bytes),
                           pixels.begin() + static_cast<std::ptrdiff_t>(i * chunk_bytes + n)));
    v1::Packet p;
    p.set_version(1);
    *p.mutable_preview_chunk() = c;
    EXPECT_EQ(wire::Validate(p), "");
    out.push_back(c);
  }
  return out;
}

using Outcome = PreviewAssembler::Outcome;

TEST(PreviewAssembler, OutOfOrderAndDuplicateChunksGiveTheImage) {
  const auto pixels = Pattern(160, 100, 1);
  auto chunks = Chunks(9, 4242, 160, 100, pixels);
  ASSERT_EQ(chunks.size(), 14u);
  std::mt19937 rng(3);
  std::shuffle(chunks.begin(), chunks.end(), rng);
  PreviewAssembler assembler;
  PreviewImage image;
  for (size_t i = 0; i + 1 < chunks.size(); ++i) {
    EXPECT_EQ(assembler.Add(chunks[i], i, &image), Outcome::kIncomplete);
    EXPECT_EQ(assembler.Add(chunks[i], i, &image), Outcome::kDuplicate);
  }
  ASSERT_EQ(assembler.Add(chunks.back(), 99, &image), Outcome::kComplete);
  EXPECT_EQ(image.node_id, 9u);
  EXPECT_EQ(image.frame_number, 4242u);
  EXPECT_EQ(image.width, 160u);
  EXPECT_EQ(image.height, 100u);
  EXPECT_FALSE(image.thresholded);
  EXPECT_EQ(image.pixels, pixels);
  EXPECT_EQ(assembler.assembling(), 0u);
}

TEST(PreviewAssembler, NewerFrameReplacesAnIncompleteOlderOne) {
  const auto old_pixels = Pattern(64, 40, 1), new_pixels = Pattern(64, 40, 2);
  const auto old_chunks = Chunks(2, 10, 64, 40, old_pixels, 500);
  const auto new_chunks = Chunks(2, 11, 64, 40, new_pixels, 500);
  PreviewAssembler assembler;
  PreviewImage image;
  EXPECT_EQ(assembler.Add(old_chunks[0], 0, &image), Outcome::kIncomplete);
  EXPECT_EQ(assembler.Add(new_chunks[1], 1, &image), Outcome::kIncomplete);
  EXPECT_EQ(assembler.Add(old_chunks[1], 2, &image), Outcome::kStale);
  Outcome last = Outcome::kIncomplete;
  for (size_t i = 0; i < new_chunks.size(); ++i)
    if (i != 1) last = assembler.Add(new_chunks[i], 3, &image);
  ASSERT_EQ(last, Outcome::kComplete);
  EXPECT_EQ(image.frame_number, 11u);
  EXPECT_EQ(image.pixels, new_pixels);
  // Once delivered, an older frame may start again (a node whose epoch was reset).
  EXPECT_EQ(assembler.Add(old_chunks[0], 4, &image), Outcome::kIncomplete);
}

TEST(PreviewAssembler, NodesAssembleSeparately) {
  const auto a = Pattern(32, 32, 1), b = Pattern(32, 32, 2);
  const auto ca = Chunks(1, 5, 32, 32, a, 600), cb = Chunks(2, 5, 32, 32, b, 600);
  PreviewAssembler assembler;
  PreviewImage image;
  EXPECT_EQ(assembler.Add(ca[0], 0, &image), Outcome::kIncomplete);
  EXPECT_EQ(assembler.Add(cb[0], 0, &image), Outcome::kIncomplete);
  ASSERT_EQ(assembler.Add(cb[1], 0, &image), Outcome::kComplete);
  EXPECT_EQ(image.pixels, b);
  ASSERT_EQ(assembler.Add(ca[1], 0, &image), Outcome::kComplete);
  EXPECT_EQ(image.pixels, a);
}

TEST(PreviewAssembler, InconsistentChunksDropTheImage) {
  const auto pixels = Pattern(40, 30, 1);
  PreviewAssembler assembler;
  PreviewImage image;
  auto chunks = Chunks(3, 1, 40, 30, pixels, 500);  // 1200 bytes: 500, 500, 200
  EXPECT_EQ(assembler.Add(chunks[0], 0, &image), Outcome::kIncomplete);
  v1::PreviewChunk other_size = chunks[1];
  other_size.set_width(30);
  other_size.set_height(40);
  EXPECT_EQ(assembler.Add(other_size, 0, &image), Outcome::kInconsistent);
  EXPECT_EQ(assembler.assembling(), 0u);

  // Three distinct chunks, the right byte count, but overlapping: a gap remains.
  chunks = Chunks(3, 2, 40, 30, pixels, 500);
  chunks[2].set_offset(400);
  chunks[2].set_data(std::string(200, 'x'));
  chunks[1].set_data(std::string(500, 'y'));
  EXPECT_EQ(assembler.Add(chunks[0], 0, &image), Outcome::kIncomplete);
  EXPECT_EQ(assembler.Add(chunks[1], 0, &image), Outcome::kIncomplete);
  EXPECT_EQ(assembler.Add(chunks[2], 0, &image), Outcome::kInconsistent);

  // More bytes than the image holds.
  chunks = Chunks(3, 3, 40, 30, pixels, 500);
  chunks[0].set_data(std::string(800, 'z'));
  EXPECT_EQ(assembler.Add(chunks[0], 0, &image), Outcome::kIncomplete);
  chunks[1].set_offset(700);
  EXPECT_EQ(assembler.Add(chunks[1], 0, &image), Outcome::kInconsistent);
}

TEST(PreviewAssembler, LimitsAndStaleness) {
  PreviewAssemblerOptions options;
  options.max_image_bytes = 1000;
  options.max_nodes = 2;
  options.stale_after_ns = 100;
  PreviewAssembler assembler(options);
  PreviewImage image;
  const auto big = Chunks(1, 1, 40, 30, Pattern(40, 30, 1), 500);
  EXPECT_EQ(assembler.Add(big[0], 0, &image), Outcome::kTooLarge);
  EXPECT_EQ(assembler.assembling(), 0u);

  for (uint32_t node = 1; node <= 3; ++node)
    EXPECT_EQ(assembler.Add(Chunks(node, 1, 20, 20, Pattern(20, 20, 1), 100)[0], node, &image),
              Outcome::kIncomplete);
  EXPECT_EQ(assembler.assembling(), 2u);  // node 1, the stalest, made room
  EXPECT_EQ(assembler.DiscardStale(102), 1u);
  EXPECT_EQ(assembler.DiscardStale(103), 1u);
  EXPECT_EQ(assembler.assembling(), 0u);
}

TEST(PreviewAssembler, PngHoldsThePixels) {
  PreviewImage image;
  image.width = 37;
  image.height = 21;
  image.pixels = Pattern(37, 21, 5);
  const std::vector<uint8_t> png = EncodePng(image);
  ASSERT_GT(png.size(), 8u);
  EXPECT_EQ(png[1], 'P');
  const cv::Mat back = cv::imdecode(png, cv::IMREAD_UNCHANGED);
  ASSERT_EQ(back.type(), CV_8UC1);
  ASSERT_EQ(back.cols, 37);
  ASSERT_EQ(back.rows, 21);
  for (int y = 0; y < back.rows; ++y)
    for (int x = 0; x < back.cols; ++x)
      ASSERT_EQ(back.at<uint8_t>(y, x), image.pixels[size_t(y) * 37 + x]) << x << "," << y;
  image.pixels.pop_back();
  EXPECT_THROW(EncodePng(image), std::runtime_error);
}

}  // namespace
}  // namespace mocap::service

// The .mca format: a round trip keeps every field (contiguous and listed frame numbers); every
// truncation, a wrong magic or version, a trailing byte and out-of-range counts are refused with
// the file's name; a file on disk reads back.
#include "archive/archive_format.h"

#include <stdexcept>

#include <gtest/gtest.h>

#include "simcore/synthetic_motion.h"
#include "util/temporary_directory_testing.h"

namespace mocap {
namespace {

CompressedTrajectories SmallArchive(bool listed_frames) {
  SyntheticMotionOptions motion_options;
  motion_options.markers = 6;
  motion_options.frames = 70;
  MarkerTrajectories motion = MakeSyntheticMotion(motion_options);
  if (listed_frames)
    for (size_t i = 0; i < motion.NumFrames(); ++i) motion.frame_numbers[i] = 5000000000ull + 3 * i + (i > 40 ? 7 : 0);
  for (size_t t = 10; t < 20; ++t) motion.At(t, 2) = MarkerTrajectories::Gap();
  TrajectoryPcaOptions options;
  options.window_frames = 32;
  return CompressTrajectories(motion, {{0, 1, 2}, {3, 4, 5}}, options);
}

void ExpectSame(const CompressedTrajectories& a, const CompressedTrajectories& b) {
  EXPECT_EQ(a.rate_hz, b.rate_hz);
  EXPECT_EQ(a.names, b.names);
  EXPECT_EQ(a.frame_numbers, b.frame_numbers);
  EXPECT_EQ(a.window_frames, b.window_frames);
  EXPECT_EQ(a.groups, b.groups);
  EXPECT_EQ(a.gap_runs, b.gap_runs);
  ASSERT_EQ(a.blocks.size(), b.blocks.size());
  for (size_t i = 0; i < a.blocks.size(); ++i) {
    EXPECT_EQ(a.blocks[i].components, b.blocks[i].components);
    EXPECT_EQ(a.blocks[i].mean, b.blocks[i].mean);
    EXPECT_EQ(a.blocks[i].time_step, b.blocks[i].time_step);
    EXPECT_EQ(a.blocks[i].time, b.blocks[i].time);
    EXPECT_EQ(a.blocks[i].weight_steps, b.blocks[i].weight_steps);
    EXPECT_EQ(a.blocks[i].weights, b.blocks[i].weights);
  }
}

TEST(ArchiveFormat, RoundTripKeepsEveryField) {
  for (bool listed : {false, true}) {
    const CompressedTrajectories archive = SmallArchive(listed);
    ExpectSame(archive, DecodeArchive(EncodeArchive(archive), "mem"));
  }
}

TEST(ArchiveFormat, EveryTruncationAndATrailingByteAreRefused) {
  const std::string bytes = EncodeArchive(SmallArchive(true));
  for (size_t length = 0; length < bytes.size(); ++length) {
    try {
      DecodeArchive(bytes.substr(0, length), "cut.mca");
      FAIL() << "accepted " << length << " of " << bytes.size() << " bytes";
    } catch (const std::runtime_error& error) {
      EXPECT_EQ(std::string(error.what()).rfind("cut.mca: ", 0), 0u) << error.what();
    }
  }
  EXPECT_THROW(DecodeArchive(bytes + '\0', "long.mca"), std::runtime_error);
}

// Overwrites the little-endian u32 at `offset`.
std::string WithU32(std::string bytes, size_t offset, uint32_t value) {
  for (int i = 0; i < 4; ++i) bytes[offset + static_cast<size_t>(i)] = static_cast<char>((value >> (8 * i)) & 0xff);
  return bytes;
}

std::string ErrorOf(const std::string& bytes) {
  try {
    DecodeArchive(bytes, "bad.mca");
  } catch (const std::runtime_error& error) {
    return error.what();
  }
  return "";
}

TEST(ArchiveFormat, RefusalsNameTheField) {
  const std::string bytes = EncodeArchive(SmallArchive(false));
  std::string wrong_magic = bytes;
  wrong_magic[0] = 'X';
  EXPECT_NE(ErrorOf(wrong_magic).find("magic"), std::string::npos);
  EXPECT_NE(ErrorOf(WithU32(bytes, 8, 3)).find("version: 3 is not supported"), std::string::npos);
  EXPECT_NE(ErrorOf(WithU32(bytes, 8, 1)).find("version: 1 (plain-varint blocks"), std::string::npos);
  // Offsets: magic 8, version 4, rate 8, then markers, frames, window.
  EXPECT_NE(ErrorOf(WithU32(bytes, 20, 0)).find("markers: 0"), std::string::npos);
  EXPECT_NE(ErrorOf(WithU32(bytes, 20, 5000)).find("markers: 5000"), std::string::npos);
  EXPECT_NE(ErrorOf(WithU32(bytes, 24, 0x7fffffff)).find("frames"), std::string::npos);
  EXPECT_NE(ErrorOf(WithU32(bytes, 28, 0)).find("window: 0"), std::string::npos);
  // A long take claimed by a short file: refused before anything the size of the take is allocated.
  EXPECT_NE(ErrorOf(WithU32(bytes, 24, 1000000)).find("blocks"), std::string::npos);
}

TEST(ArchiveFormat, FileRoundTripAndExtension) {
  const testing::TemporaryDirectory dir("archive_format");
  const std::string path = dir.File("take.mca");
  const CompressedTrajectories archive = SmallArchive(false);
  WriteArchiveFile(archive, path);
  ExpectSame(archive, ReadArchiveFile(path));
  EXPECT_THROW(ReadArchiveFile(dir.File("missing.mca")), std::runtime_error);
  EXPECT_TRUE(IsArchivePath("a/B.MCA"));
  EXPECT_FALSE(IsArchivePath("a/b.trc"));
  EXPECT_FALSE(IsArchivePath("mca"));
}

}  // namespace
}  // namespace mocap

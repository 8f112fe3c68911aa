// Session directories: write/read round trip, reordering, damaged logs, bad session.json.
#include "ingest/session.h"

#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "ingest/frame_codec.h"

namespace mocap {
namespace {
namespace fs = std::filesystem;

fs::path TempDir(const std::string& name) {
  fs::path dir = fs::temp_directory_path() / ("mocap_session_test_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  return dir;
}

CameraFrame MakeFrame(uint32_t camera, uint64_t number, int blobs) {
  CameraFrame f;
  f.camera_id = camera;
  f.frame_number = number;
  f.width = 1280;
  f.height = 800;
  for (int i = 0; i < blobs; ++i) {
    Blob b;
    b.pixel = Eigen::Vector2d(10.0 + i * 4.25 + camera * 0.5, 20.0 + number * 0.125);
    b.area = 12 + i;
    b.peak = 250;
    b.mean = 180;
    f.blobs.push_back(b);
  }
  return f;
}

SessionInfo Info() {
  SessionInfo info;
  info.rate_hz = 240.0;
  info.camera_ids = {1, 2, 3};
  info.source = "test";
  return info;
}

TEST(Session, RoundTripGroupsCamerasByFrameNumber) {
  const fs::path dir = TempDir("roundtrip");
  SessionWriter writer;
  writer.Create(dir.string(), Info());
  for (uint64_t n = 0; n < 20; ++n)
    for (uint32_t cam = 1; cam <= 3; ++cam)
      if (!(n == 7 && cam == 2)) writer.Write(MakeFrame(cam, n, 100));  // 100 markers: 3 chunks
  writer.Finish();

  SessionReader reader;
  reader.Open(dir.string());
  EXPECT_EQ(reader.Info().rate_hz, 240.0);
  EXPECT_EQ(reader.Info().camera_frames, 59u);
  FrameSet set;
  uint64_t expected = 0;
  while (reader.Next(&set)) {
    EXPECT_EQ(set.frame_number, expected);
    EXPECT_EQ(set.cameras.size(), expected == 7 ? 2u : 3u);
    for (const CameraFrame& f : set.cameras) {
      const CameraFrame truth = MakeFrame(f.camera_id, f.frame_number, 100);
      ASSERT_EQ(f.blobs.size(), truth.blobs.size());
      for (size_t i = 0; i < f.blobs.size(); ++i)
        EXPECT_NEAR((f.blobs[i].pixel - truth.blobs[i].pixel).norm(), 0.0, 1.0 / 256);
    }
    ++expected;
  }
  EXPECT_EQ(expected, 20u);
  EXPECT_TRUE(reader.warnings().empty());
  fs::remove_all(dir);
}

TEST(Session, OutOfOrderArrivalIsSortedWithinTheWindow) {
  const fs::path dir = TempDir("reorder");
  SessionWriter writer;
  writer.Create(dir.string(), Info());
  for (uint64_t n : {3, 1, 2, 0, 5, 4}) writer.Write(MakeFrame(1, n, 2));
  writer.Finish();
  SessionReader reader(8);
  reader.Open(dir.string());
  FrameSet set;
  std::vector<uint64_t> order;
  while (reader.Next(&set)) order.push_back(set.frame_number);
  EXPECT_EQ(order, (std::vector<uint64_t>{0, 1, 2, 3, 4, 5}));
}

TEST(Session, TruncatedLogKeepsEverythingBeforeTheTornRecord) {
  const fs::path dir = TempDir("truncated");
  SessionWriter writer;
  writer.Create(dir.string(), Info());
  for (uint64_t n = 0; n < 10; ++n) writer.Write(MakeFrame(1, n, 3));
  writer.Finish();
  const fs::path log = dir / "raw.mlog";
  fs::resize_file(log, fs::file_size(log) - 5);

  SessionReader reader;
  reader.Open(dir.string());
  FrameSet set;
  int count = 0;
  while (reader.Next(&set)) ++count;
  EXPECT_EQ(count, 9);
  ASSERT_FALSE(reader.warnings().empty());
  EXPECT_NE(reader.warnings()[0].find("truncated"), std::string::npos);
}

TEST(Session, CorruptRecordStopsReadingWithWarning) {
  const fs::path dir = TempDir("corrupt");
  SessionWriter writer;
  writer.Create(dir.string(), Info());
  for (uint64_t n = 0; n < 10; ++n) writer.Write(MakeFrame(1, n, 3));
  writer.Finish();
  const fs::path log = dir / "raw.mlog";
  std::fstream f(log, std::ios::in | std::ios::out | std::ios::binary);
  f.seekp(static_cast<std::streamoff>(fs::file_size(log) / 2));
  f.put('\x55');
  f.close();
  SessionReader reader;
  reader.Open(dir.string());
  FrameSet set;
  int count = 0;
  while (reader.Next(&set)) ++count;
  EXPECT_GT(count, 2);
  EXPECT_LT(count, 10);
  EXPECT_FALSE(reader.warnings().empty());
}

TEST(Session, ForeignDatagramsAreCountedNotFatal) {
  const fs::path dir = TempDir("foreign");
  SessionWriter writer;
  writer.Create(dir.string(), Info());
  writer.Write(MakeFrame(1, 0, 3));
  const uint8_t junk[] = {1, 2, 3, 4, 5};
  writer.AppendDatagram(junk, sizeof junk, 0);
  writer.Write(MakeFrame(1, 1, 3));
  writer.Finish();
  SessionReader reader;
  reader.Open(dir.string());
  FrameSet set;
  int count = 0;
  while (reader.Next(&set)) ++count;
  EXPECT_EQ(count, 2);
  EXPECT_EQ(reader.stats().malformed, 1u);
}

TEST(Session, BadSessionJsonIsRefusedWithReason) {
  const fs::path dir = TempDir("badjson");
  fs::create_directories(dir);
  std::ofstream(dir / "session.json") << "{\"format\": \"mocap-session\", \"version\": 1, \"cameras\": [1]}";
  SessionReader reader;
  try {
    reader.Open(dir.string());
    FAIL() << "accepted a session without rate";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("session.json"), std::string::npos);
  }
  std::ofstream(dir / "session.json") << "not json";
  EXPECT_THROW(reader.Open(dir.string()), std::runtime_error);
  EXPECT_THROW(reader.Open((dir / "missing").string()), std::runtime_error);
}

// Reads every frame set; returns their frame numbers.
std::vector<uint64_t> ReadFrameNumbers(SessionReader* reader) {
  std::vector<uint64_t> out;
  FrameSet set;
  while (reader->Next(&set)) out.push_back(set.frame_number);
  return out;
}

// A corrupt or forged frame number is skipped and counted, wherever it sits in the log; the
// reader's work follows the records, not the frame numbers' values.
TEST(Session, ImplausibleFrameNumbersAreSkippedAndCounted) {
  for (const uint64_t forged : {uint64_t{1'000'000'000}, uint64_t{1} << 63, ~uint64_t{0}}) {
    for (const bool forged_first : {false, true}) {
      const fs::path dir = TempDir("forged");
      SessionWriter writer;
      writer.Create(dir.string(), Info());
      if (forged_first) writer.Write(MakeFrame(1, forged, 0));
      for (uint64_t n = 0; n < 10; ++n)
        for (uint32_t cam = 1; cam <= 3; ++cam) writer.Write(MakeFrame(cam, n, 0));
      if (!forged_first) writer.Write(MakeFrame(2, forged, 0));
      writer.Finish();

      SessionReader reader;
      reader.Open(dir.string());
      std::vector<uint64_t> expected(10);
      for (uint64_t n = 0; n < 10; ++n) expected[n] = n;
      EXPECT_EQ(ReadFrameNumbers(&reader), expected) << forged << (forged_first ? " first" : " last");
      EXPECT_EQ(reader.stats().implausible_frames, 1u);
      ASSERT_EQ(reader.warnings().size(), 1u);
      EXPECT_NE(reader.warnings()[0].find("1 camera frames skipped"), std::string::npos);
      fs::remove_all(dir);
    }
  }
}

// A pause within the bound is a legitimate gap: its frames are kept, in order.
TEST(Session, PausesUpToTheBoundAreKept) {
  const fs::path dir = TempDir("pause");
  SessionWriter writer;
  writer.Create(dir.string(), Info());
  const uint64_t gap = MaxFrameGap(Info());
  const std::vector<uint64_t> numbers = {0, 1, 1 + gap, 2 + gap, 2 + 2 * gap + 1};
  for (uint64_t n : numbers) writer.Write(MakeFrame(1, n, 0));
  writer.Finish();
  SessionReader reader;
  reader.Open(dir.string());
  EXPECT_EQ(ReadFrameNumbers(&reader), (std::vector<uint64_t>{0, 1, 1 + gap, 2 + gap}));
  EXPECT_EQ(reader.stats().implausible_frames, 1u);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace mocap

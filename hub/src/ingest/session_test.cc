// Session directories: write/read round trip, reordering, damaged logs, bad session.json.
#include "ingest/session.h"

#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>

#include <gtest/gtest.h>

#include "ingest/camera_frame_testing.h"
#include "ingest/frame_codec.h"
#include "util/temporary_directory_testing.h"

namespace mocap {
namespace {
namespace fs = std::filesystem;

SessionInfo Info() {
  SessionInfo info;
  info.rate_hz = 240.0;
  info.camera_ids = {1, 2, 3};
  info.source = "test";
  return info;
}

// Reads every frame set; returns their frame numbers.
std::vector<uint64_t> FrameNumbers(SessionReader* reader) {
  std::vector<uint64_t> out;
  FrameSet set;
  while (reader->Next(&set)) out.push_back(set.frame_number);
  return out;
}

TEST(Session, RoundTripGroupsCamerasByFrameNumber) {
  const testing::TemporaryDirectory temp("session_test");
  const fs::path& dir = temp.path();
  SessionWriter writer;
  writer.Create(dir.string(), Info());
  for (uint64_t n = 0; n < 20; ++n)
    for (uint32_t cam = 1; cam <= 3; ++cam)
      if (!(n == 7 && cam == 2)) writer.Write(testing::FrameOfBlobs(cam, n, 100));  // 100 markers: 3 chunks
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
      const CameraFrame truth = testing::FrameOfBlobs(f.camera_id, f.frame_number, 100);
      ASSERT_EQ(f.blobs.size(), truth.blobs.size());
      for (size_t i = 0; i < f.blobs.size(); ++i)
        EXPECT_NEAR((f.blobs[i].pixel - truth.blobs[i].pixel).norm(), 0.0, 1.0 / 256);
    }
    ++expected;
  }
  EXPECT_EQ(expected, 20u);
  EXPECT_TRUE(reader.warnings().empty());
}

TEST(Session, OutOfOrderArrivalIsSortedWithinTheWindow) {
  const testing::TemporaryDirectory temp("session_test");
  const fs::path& dir = temp.path();
  SessionWriter writer;
  writer.Create(dir.string(), Info());
  for (uint64_t n : {3, 1, 2, 0, 5, 4}) writer.Write(testing::FrameOfBlobs(1, n, 2));
  writer.Finish();
  SessionReader reader(8);
  reader.Open(dir.string());
  EXPECT_EQ(FrameNumbers(&reader), (std::vector<uint64_t>{0, 1, 2, 3, 4, 5}));
}

TEST(Session, TruncatedLogKeepsEverythingBeforeTheTornRecord) {
  const testing::TemporaryDirectory temp("session_test");
  const fs::path& dir = temp.path();
  SessionWriter writer;
  writer.Create(dir.string(), Info());
  for (uint64_t n = 0; n < 10; ++n) writer.Write(testing::FrameOfBlobs(1, n, 3));
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

// A session in dir of ten frames of camera 1 (one record each), then `damage` applied to the raw
// log's bytes.
void DamagedSession(const fs::path& dir, const std::function<void(std::string*)>& damage) {
  SessionWriter writer;
  writer.Create(dir.string(), Info());
  for (uint64_t n = 0; n < 10; ++n) writer.Write(testing::FrameOfBlobs(1, n, 3));
  writer.Finish();
  const fs::path log = dir / "raw.mlog";
  std::string bytes;
  {
    std::ifstream in(log, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), {});
  }
  damage(&bytes);
  std::ofstream(log, std::ios::binary | std::ios::trunc) << bytes;
}

// Byte offset of record k (0-based) in an undamaged log, walked by the records' lengths.
size_t RecordStart(const std::string& bytes, int k) {
  size_t at = 16;
  for (int i = 0; i < k; ++i) {
    uint32_t size = 0;
    for (int b = 3; b >= 0; --b) size = (size << 8) | static_cast<uint8_t>(bytes[at + 4 + b]);
    at += 20 + size;
  }
  return at;
}

TEST(Session, AFlippedByteCostsOnlyItsRecord) {
  // The probe: one flipped byte at 10 % of a raw log kept 16 of 151 frames. Now the reader
  // resynchronises on the next good record: only the damaged record's frame is lost.
  const testing::TemporaryDirectory temp("session_test");
  const fs::path& dir = temp.path();
  DamagedSession(dir, [](std::string* b) { (*b)[RecordStart(*b, 3) + 25] ^= 0x04; });
  SessionReader reader;
  reader.Open(dir.string());
  EXPECT_EQ(FrameNumbers(&reader), (std::vector<uint64_t>{0, 1, 2, 4, 5, 6, 7, 8, 9}));
  EXPECT_EQ(reader.stats().damaged_log_stretches, 1u);
  std::string bytes;
  {
    std::ifstream in(dir / "raw.mlog", std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), {});
  }
  const size_t record = RecordStart(bytes, 4) - RecordStart(bytes, 3);
  EXPECT_EQ(reader.stats().skipped_log_bytes, record);
  ASSERT_FALSE(reader.warnings().empty());
  EXPECT_NE(reader.warnings()[0].find("skipped 1 damaged stretch (" + std::to_string(record) + " bytes"),
            std::string::npos)
      << reader.warnings()[0];
  EXPECT_NE(reader.warnings()[0].find("CRC mismatch"), std::string::npos) << reader.warnings()[0];
  EXPECT_NE(reader.warnings()[0].find("kept 9 good records"), std::string::npos) << reader.warnings()[0];
}

TEST(Session, DamagedHeadersLengthsAndLostBlocksAreSkipped) {
  struct Case {
    const char* name;
    std::function<void(std::string*)> damage;
    std::vector<uint64_t> frames;
    const char* why;
  };
  const std::vector<Case> cases = {
      {"magic", [](std::string* b) { (*b)[RecordStart(*b, 0)] = 'X'; }, {1, 2, 3, 4, 5, 6, 7, 8, 9}, "bad record magic"},
      // A length that still fits the limit: the reader must not trust it and skip good records.
      {"length", [](std::string* b) { (*b)[RecordStart(*b, 5) + 5] = 0x20; }, {0, 1, 2, 3, 4, 6, 7, 8, 9},
       "truncated record"},
      {"huge_length", [](std::string* b) { (*b)[RecordStart(*b, 5) + 7] = 0x7f; }, {0, 1, 2, 3, 4, 6, 7, 8, 9},
       "impossible record length"},
      // A block of zeros over records 2-4 (a lost disk block), and bytes inserted between records.
      {"zeros", [](std::string* b) { std::fill(b->begin() + RecordStart(*b, 2) + 3, b->begin() + RecordStart(*b, 5) - 2, 0); },
       {0, 1, 5, 6, 7, 8, 9}, "bad record magic"},
      {"inserted", [](std::string* b) { b->insert(RecordStart(*b, 7), "MCR1 garbage MCR1\x10"); },
       {0, 1, 2, 3, 4, 5, 6, 7, 8, 9}, "impossible record length"},
  };
  for (const Case& c : cases) {
    const testing::TemporaryDirectory temp("session_test");
    const fs::path& dir = temp.path();
    DamagedSession(dir, c.damage);
    SessionReader reader;
    reader.Open(dir.string());
    EXPECT_EQ(FrameNumbers(&reader), c.frames) << c.name;
    EXPECT_EQ(reader.stats().damaged_log_stretches, 1u) << c.name;
    ASSERT_FALSE(reader.warnings().empty()) << c.name;
    EXPECT_NE(reader.warnings()[0].find(c.why), std::string::npos) << c.name << ": " << reader.warnings()[0];
  }
}

TEST(Session, DamageRunningToTheEndIsReportedAsATornTail) {
  const testing::TemporaryDirectory temp("session_test");
  const fs::path& dir = temp.path();
  DamagedSession(dir, [](std::string* b) { (*b)[RecordStart(*b, 5) + 30] ^= 1; b->resize(b->size() - 7); });
  SessionReader reader;
  reader.Open(dir.string());
  EXPECT_EQ(FrameNumbers(&reader), (std::vector<uint64_t>{0, 1, 2, 3, 4, 6, 7, 8}));
  EXPECT_EQ(reader.stats().damaged_log_stretches, 2u);
  ASSERT_FALSE(reader.warnings().empty());
  const std::string warning = reader.warnings()[0];
  EXPECT_NE(warning.find("skipped 1 damaged stretch"), std::string::npos) << warning;
  EXPECT_NE(warning.find("CRC mismatch"), std::string::npos) << warning;
  EXPECT_NE(warning.find("the last"), std::string::npos) << warning;
  EXPECT_NE(warning.find("(truncated record)"), std::string::npos) << warning;
}

TEST(Session, AnUnknownLogVersionIsRefusedWithWhatThisReaderReads) {
  const testing::TemporaryDirectory temp("session_test");
  const fs::path& dir = temp.path();
  DamagedSession(dir, [](std::string* b) { (*b)[8] = 2; });
  SessionReader reader;
  try {
    reader.Open(dir.string());
    FAIL() << "a version 2 log was opened";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("session log version 2 is not one this mocap-hub reads"), std::string::npos)
        << e.what();
  }
}

TEST(Session, FramesOfAnotherImageSizeThanTheCalibrationsAreRescaledOrRefused) {
  // The probe: a node at 640x400 against a calibration at 1280x800 was used as it was. Camera 2
  // here sends a binned mode (same aspect: rescaled), camera 3 a crop (another aspect: refused).
  const testing::TemporaryDirectory temp("session_test");
  const fs::path& dir = temp.path();
  SessionWriter writer;
  writer.Create(dir.string(), Info());
  for (uint64_t n = 0; n < 5; ++n) {
    writer.Write(testing::FrameOfBlobs(1, n, 2));
    CameraFrame binned = testing::FrameOfBlobs(2, n, 2);
    binned.width = 640;
    binned.height = 400;
    writer.Write(binned);
    CameraFrame cropped = testing::FrameOfBlobs(3, n, 2);
    cropped.width = 640;
    cropped.height = 480;
    writer.Write(cropped);
  }
  writer.Finish();

  SessionReader reader;
  reader.Open(dir.string());
  reader.CheckImageSizes({{1, {1280, 800}}, {2, {1280, 800}}, {3, {1280, 800}}});
  FrameSet set;
  int sets = 0;
  while (reader.Next(&set)) {
    ++sets;
    ASSERT_EQ(set.cameras.size(), 2u);  // camera 3 refused
    EXPECT_EQ(set.cameras[0].blobs[0].pixel, testing::FrameOfBlobs(1, set.frame_number, 2).blobs[0].pixel);
    const Eigen::Vector2d binned = testing::FrameOfBlobs(2, set.frame_number, 2).blobs[0].pixel;
    EXPECT_NEAR((set.cameras[1].blobs[0].pixel - ((binned.array() + 0.5) * 2.0 - 0.5).matrix()).norm(), 0.0, 1e-9);
    EXPECT_EQ(set.cameras[1].width, 1280u);
  }
  EXPECT_EQ(sets, 5);
  EXPECT_EQ(reader.stats().rescaled_frames, 5u);
  EXPECT_EQ(reader.stats().wrong_size_frames, 5u);
  std::string all;
  for (const std::string& w : reader.warnings()) all += w + "\n";
  EXPECT_NE(all.find("camera 2: images of 640x400 against a calibration at 1280x800: 5 frames rescaled"),
            std::string::npos)
      << all;
  EXPECT_NE(all.find("camera 3: images of 640x480 against a calibration at 1280x800: 5 frames refused"),
            std::string::npos)
      << all;
}

TEST(Session, ForeignDatagramsAreCountedNotFatal) {
  const testing::TemporaryDirectory temp("session_test");
  const fs::path& dir = temp.path();
  SessionWriter writer;
  writer.Create(dir.string(), Info());
  writer.Write(testing::FrameOfBlobs(1, 0, 3));
  const uint8_t junk[] = {1, 2, 3, 4, 5};
  writer.AppendDatagram(junk, sizeof junk, 0);
  writer.Write(testing::FrameOfBlobs(1, 1, 3));
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
  const testing::TemporaryDirectory temp("session_test");
  const fs::path& dir = temp.path();
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
  // Fields of another type than expected are refused the same way, not thrown as type errors.
  std::ofstream(dir / "session.json") << "{\"format\": 1, \"version\": 1, \"rate_hz\": 100, \"cameras\": [1]}";
  EXPECT_THROW(reader.Open(dir.string()), std::runtime_error);
  std::ofstream(dir / "session.json") << "{\"format\": \"mocap-session\", \"version\": \"1\", \"rate_hz\": 100, \"cameras\": [1]}";
  EXPECT_THROW(reader.Open(dir.string()), std::runtime_error);
  EXPECT_THROW(reader.Open((dir / "missing").string()), std::runtime_error);
}

// Counts, times and camera ids are integers from 0 up: a float past the type's range (the
// session fuzzer's "epoch_ns": 1.5e48, undefined behaviour in the conversion) or a negative
// number (which wrapped to a huge id) is refused naming the field, not converted.
TEST(Session, OutOfRangeNumbersAreRefusedNamingTheField) {
  const testing::TemporaryDirectory temp("session_test");
  const fs::path& dir = temp.path();
  auto refusal = [&](const std::string& fields) {
    std::ofstream(dir / "session.json") << "{\"format\": \"mocap-session\", \"version\": 1, \"rate_hz\": 100, " + fields + "}";
    try {
      LoadSessionInfo(dir.string());
    } catch (const std::runtime_error& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_NE(refusal("\"cameras\": [1], \"epoch_ns\": 1.5e48").find("epoch_ns"), std::string::npos);
  EXPECT_NE(refusal("\"cameras\": [1], \"epoch_ns\": -5").find("epoch_ns"), std::string::npos);
  EXPECT_NE(refusal("\"cameras\": [1], \"frame_sets\": 2.5").find("frame_sets"), std::string::npos);
  EXPECT_NE(refusal("\"cameras\": [1], \"camera_frames\": 1e30").find("camera_frames"), std::string::npos);
  EXPECT_NE(refusal("\"cameras\": [1], \"dropped_camera_frames\": -1").find("dropped_camera_frames"),
            std::string::npos);
  EXPECT_NE(refusal("\"cameras\": [-1]").find("camera id"), std::string::npos);
  EXPECT_NE(refusal("\"cameras\": [1e20]").find("camera id"), std::string::npos);
  EXPECT_NE(refusal("\"cameras\": [4294967296]").find("camera id"), std::string::npos);
  EXPECT_NE(refusal("\"cameras\": 1").find("cameras"), std::string::npos);
  EXPECT_NE(refusal("\"cameras\": [1]").find("accepted"), std::string::npos);
  const SessionInfo info = LoadSessionInfo(dir.string());
  EXPECT_EQ(info.camera_ids, std::vector<uint32_t>{1});
  refusal("\"cameras\": [4294967295], \"epoch_ns\": 18446744073709551615");
  EXPECT_EQ(LoadSessionInfo(dir.string()).epoch_ns, 18446744073709551615ull);
}

// A corrupt or forged frame number is skipped and counted, wherever it sits in the log; the
// reader's work follows the records, not the frame numbers' values.
TEST(Session, ImplausibleFrameNumbersAreSkippedAndCounted) {
  for (const uint64_t forged : {uint64_t{1'000'000'000}, uint64_t{1} << 63, ~uint64_t{0}}) {
    for (const bool forged_first : {false, true}) {
      const testing::TemporaryDirectory temp("session_test");
      const fs::path& dir = temp.path();
      SessionWriter writer;
      writer.Create(dir.string(), Info());
      if (forged_first) writer.Write(testing::FrameOfBlobs(1, forged, 0));
      for (uint64_t n = 0; n < 10; ++n)
        for (uint32_t cam = 1; cam <= 3; ++cam) writer.Write(testing::FrameOfBlobs(cam, n, 0));
      if (!forged_first) writer.Write(testing::FrameOfBlobs(2, forged, 0));
      writer.Finish();

      SessionReader reader;
      reader.Open(dir.string());
      std::vector<uint64_t> expected(10);
      for (uint64_t n = 0; n < 10; ++n) expected[n] = n;
      EXPECT_EQ(FrameNumbers(&reader), expected) << forged << (forged_first ? " first" : " last");
      EXPECT_EQ(reader.stats().implausible_frames, 1u);
      ASSERT_EQ(reader.warnings().size(), 1u);
      EXPECT_NE(reader.warnings()[0].find("1 camera frames skipped"), std::string::npos);
    }
  }
}

// A pause within the bound is a legitimate gap: its frames are kept, in order.
TEST(Session, PausesUpToTheBoundAreKept) {
  const testing::TemporaryDirectory temp("session_test");
  const fs::path& dir = temp.path();
  SessionWriter writer;
  writer.Create(dir.string(), Info());
  const uint64_t gap = MaxFrameGap(Info());
  const std::vector<uint64_t> numbers = {0, 1, 1 + gap, 2 + gap, 2 + 2 * gap + 1};
  for (uint64_t n : numbers) writer.Write(testing::FrameOfBlobs(1, n, 0));
  writer.Finish();
  SessionReader reader;
  reader.Open(dir.string());
  EXPECT_EQ(FrameNumbers(&reader), (std::vector<uint64_t>{0, 1, 1 + gap, 2 + gap}));
  EXPECT_EQ(reader.stats().implausible_frames, 1u);
}

}  // namespace
}  // namespace mocap

// C3D: what the writer writes the reader reads back (names, rate, frame numbers, gaps, skipped
// frames, labels past 255 points); the header and parameters say what the standard says; files
// cut short keep their frames; files of other shapes (integer data, analog channels) are read;
// broken files get reasons. (tests/c3d/c3d_interop.py reads our files with ezc3d and c3d.)
#include "io/c3d.h"

#include <cmath>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>

#include <gtest/gtest.h>

#include "io/live_points.h"
#include "io/trajectory_file.h"
#include "util/special_file_testing.h"
#include "util/temporary_directory_testing.h"

namespace mocap {
namespace {

std::vector<uint8_t> Bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

MarkerTrajectories Sample(size_t markers, size_t frames, uint64_t first_frame) {
  MarkerTrajectories t;
  t.rate_hz = 240.0;
  for (size_t m = 0; m < markers; ++m) t.names.push_back(m == 0 ? "LASI" : "marker_" + std::to_string(m));
  for (size_t f = 0; f < frames; ++f) {
    const size_t i = t.AddFrame(first_frame + f);
    for (size_t m = 0; m < markers; ++m)
      if ((f + m) % 7 != 3) t.At(i, m) = {100.0 * static_cast<double>(m) + 0.25, -50.5 + static_cast<double>(f), 1234.5};
  }
  return t;
}

void ExpectSame(const MarkerTrajectories& a, const MarkerTrajectories& b) {
  ASSERT_EQ(a.names, b.names);
  EXPECT_DOUBLE_EQ(a.rate_hz, b.rate_hz);
  ASSERT_EQ(a.frame_numbers, b.frame_numbers);
  for (size_t f = 0; f < a.NumFrames(); ++f)
    for (size_t m = 0; m < a.NumMarkers(); ++m) {
      ASSERT_EQ(a.Has(f, m), b.Has(f, m)) << "frame " << f << " marker " << m;
      if (a.Has(f, m)) {
        EXPECT_LT((a.At(f, m) - b.At(f, m)).norm(), 1e-3);
      }
    }
}

TEST(C3d, RoundTrip) {
  const testing::TemporaryDirectory temp("c3d_test");
  const std::string path = temp.File("round.c3d");
  const MarkerTrajectories t = Sample(5, 50, 1000);
  WriteC3d(t, path);
  ExpectSame(t, ReadC3d(path));
  // What the standard fixes: the key, the first parameter block, float data, Intel.
  const std::vector<uint8_t> b = Bytes(path);
  ASSERT_GE(b.size(), 1024u);
  EXPECT_EQ(b[0], 2);
  EXPECT_EQ(b[1], 0x50);
  EXPECT_EQ(b[2] | (b[3] << 8), 5);            // points
  EXPECT_EQ(b[8] | (b[9] << 8), 50);           // last frame (first is 1)
  float scale, rate;
  std::memcpy(&scale, &b[12], 4);
  std::memcpy(&rate, &b[20], 4);
  EXPECT_LT(scale, 0.0f);
  EXPECT_FLOAT_EQ(rate, 240.0f);
  EXPECT_EQ(b[512 + 1], 0x50);
  EXPECT_EQ(b[512 + 3], 84);
  const size_t data_start = b[16] | (b[17] << 8);
  EXPECT_EQ(b.size(), (data_start - 1) * 512 + 50 * 5 * 16);
}

TEST(C3d, SkippedFramesBecomeGapsAndManyLabelsSplit) {
  const testing::TemporaryDirectory temp("c3d_test");
  const std::string path = temp.File("many.c3d");
  MarkerTrajectories t = Sample(300, 4, 0);
  C3dWriter w;
  w.Open(path, t.names, t.rate_hz);
  w.WriteFrame(10, &t.points[0], 300);
  w.WriteFrame(13, &t.points[300], 300);  // 11 and 12 were never seen
  EXPECT_THROW(w.WriteFrame(12, &t.points[600], 300), std::runtime_error);
  EXPECT_THROW(w.WriteFrame(13 + C3dWriter::kMaxSkippedFrames + 2, &t.points[600], 300), std::runtime_error);
  w.Close();
  const MarkerTrajectories r = ReadC3d(path);
  EXPECT_EQ(r.names, t.names);  // LABELS holds 255, LABELS2 the rest
  ASSERT_EQ(r.frame_numbers, (std::vector<uint64_t>{10, 11, 12, 13}));
  for (size_t m = 0; m < 300; ++m) {
    EXPECT_FALSE(r.Has(1, m));
    EXPECT_FALSE(r.Has(2, m));
    EXPECT_EQ(r.Has(3, m), t.Has(1, m));
  }
}

TEST(C3d, CutShortKeepsWholeFrames) {
  const testing::TemporaryDirectory temp("c3d_test");
  const std::string path = temp.File("cut.c3d");
  WriteC3d(Sample(3, 20, 0), path);
  std::vector<uint8_t> b = Bytes(path);
  b.resize(b.size() - 3 * 16 * 5 - 7);  // five and a bit frames lost
  const MarkerTrajectories r = ParseC3d(b, "cut");
  EXPECT_EQ(r.NumFrames(), 14u);
}

// POINT:LONG_FRAMES is a float: a damaged one past any count (4e20) is a promise like any
// other, and the file keeps the frames it holds (converting it to a count was undefined).
TEST(C3d, AFrameCountPastAnyIntegerKeepsTheFramesHeld) {
  const testing::TemporaryDirectory temp("c3d_test");
  const std::string path = temp.File("long_frames.c3d");
  WriteC3d(Sample(3, 20, 0), path);
  std::vector<uint8_t> b = Bytes(path);
  const std::string name = "LONG_FRAMES";
  const auto at = std::search(b.begin(), b.end(), name.begin(), name.end());
  ASSERT_NE(at, b.end());
  // name, then the offset to the next parameter (2 bytes), the type (4: float), no dimensions.
  const size_t record = static_cast<size_t>(at - b.begin()) + name.size();
  ASSERT_EQ(static_cast<int8_t>(b[record + 2]), 4);
  ASSERT_EQ(b[record + 3], 0);
  const float huge = 4e20f;
  std::memcpy(&b[record + 4], &huge, sizeof huge);
  EXPECT_EQ(ParseC3d(b, "long_frames").NumFrames(), 20u);
}

// A file as other tools write it: integer data with a scale, two analog samples per frame,
// 4-character labels, no TRIAL group; built by hand here.
TEST(C3d, ReadsIntegerDataWithAnalogChannels) {
  std::vector<uint8_t> f(3 * 512, 0);
  auto u16 = [&](size_t at, uint16_t v) { f[at] = v & 0xff, f[at + 1] = v >> 8; };
  auto f32 = [&](size_t at, float v) { std::memcpy(&f[at], &v, 4); };
  f[0] = 2, f[1] = 0x50;
  u16(2, 2), u16(4, 2), u16(6, 1), u16(8, 3);  // 2 points, 2 analog values per frame, frames 1..3
  f32(12, 0.5f), u16(16, 4), f32(20, 100.0f);  // data from block 4
  size_t p = 512;
  f[p++] = 1, f[p++] = 0x50, f[p++] = 1, f[p++] = 84;
  auto record = [&](int8_t id, const std::string& name, const std::vector<uint8_t>& body, bool last) {
    f[p++] = static_cast<uint8_t>(name.size());
    f[p++] = static_cast<uint8_t>(id);
    for (char c : name) f[p++] = static_cast<uint8_t>(c);
    u16(p, last ? 0 : static_cast<uint16_t>(2 + body.size()));
    p += 2;
    for (uint8_t c : body) f[p++] = c;
  };
  record(-1, "POINT", {0}, false);
  record(1, "LABELS", {0xff, 2, 4, 2, 'R', 'H', 'E', 'E', 'L', 'T', 'O', 'E', 0}, false);
  record(1, "USED", {2, 0, 2, 0, 0}, true);
  std::vector<uint8_t> data;
  for (int frame = 0; frame < 3; ++frame) {
    for (int m = 0; m < 2; ++m) {
      const int16_t v[4] = {static_cast<int16_t>(10 * frame + m), 20, 30, static_cast<int16_t>(m == 1 && frame == 1 ? -1 : 4)};
      for (int16_t x : v) data.push_back(static_cast<uint8_t>(x & 0xff)), data.push_back(static_cast<uint8_t>((x >> 8) & 0xff));
    }
    for (int a = 0; a < 4; ++a) data.push_back(0x7f);  // 2 analog int16 samples
  }
  f.insert(f.end(), data.begin(), data.end());
  const MarkerTrajectories r = ParseC3d(f, "hand-made");
  EXPECT_EQ(r.names, (std::vector<std::string>{"RHEE", "LTOE"}));
  EXPECT_DOUBLE_EQ(r.rate_hz, 100.0);
  ASSERT_EQ(r.NumFrames(), 3u);
  EXPECT_EQ(r.frame_numbers[0], 0u);
  EXPECT_TRUE(r.Has(2, 1));
  EXPECT_FALSE(r.Has(1, 1));
  EXPECT_DOUBLE_EQ(r.At(2, 1).x(), 21 * 0.5);
  EXPECT_DOUBLE_EQ(r.At(2, 1).z(), 15.0);
}

TEST(C3d, BrokenFilesGetReasons) {
  const testing::TemporaryDirectory temp("c3d_test");
  auto error = [](const std::vector<uint8_t>& bytes) {
    try {
      ParseC3d(bytes, "bad.c3d");
    } catch (const std::runtime_error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(error({1, 2, 3}).find("too short"), std::string::npos);
  EXPECT_NE(error(std::vector<uint8_t>(600, 0)).find("not a C3D"), std::string::npos);
  const std::string path = temp.File("dec.c3d");
  WriteC3d(Sample(2, 3, 0), path);
  std::vector<uint8_t> b = Bytes(path);
  b[512 + 3] = 85;
  EXPECT_NE(error(b).find("DEC"), std::string::npos);
  b[512 + 3] = 84;
  b[0] = 200;  // parameters past the end
  EXPECT_NE(error(b).find("past the end"), std::string::npos);
  EXPECT_THROW(ReadC3d(temp.File("missing.c3d")), std::runtime_error);
  C3dWriter w;
  EXPECT_THROW(w.Open(temp.File("x.c3d"), {}, 100.0), std::runtime_error);
  EXPECT_THROW(w.Open(temp.File("x.c3d"), {"A"}, 0.0), std::runtime_error);
}

// A C3D file is read whole: a FIFO was waited on (and /dev/zero grew without end: not tried
// here, as without the check it would take all memory). Refused at once now, naming the path.
TEST(C3d, ReadsOnlyRegularFiles) {
  const auto read = [](const std::string& path) { ReadC3d(path); };
  const std::string fifo = testing::ErrorOfReadingAFifo(read, "take.c3d");
  EXPECT_NE(fifo.find("take.c3d: not a regular file (a FIFO)"), std::string::npos) << fifo;
}

TEST(TrajectoryFile, ByExtension) {
  const testing::TemporaryDirectory temp("c3d_test");
  EXPECT_EQ(TrajectoryFormatOf("a/b.TRC"), TrajectoryFormat::kTrc);
  EXPECT_EQ(TrajectoryFormatOf("x.c3d"), TrajectoryFormat::kC3d);
  EXPECT_THROW(TrajectoryFormatOf("x.csv"), std::invalid_argument);
  const MarkerTrajectories t = Sample(3, 10, 5);
  const std::string trc = temp.File("t.trc"), c3d = temp.File("t.c3d");
  WriteTrajectories(t, trc);
  WriteTrajectories(ReadTrajectories(trc), c3d);
  ExpectSame(ReadTrajectories(trc), ReadTrajectories(c3d));
}

// A capture's live points read like any marker file (labels apply, convert), each track a column;
// writing one is refused, before anything is written.
TEST(TrajectoryFile, LivePointsAreReadNeverWritten) {
  const testing::TemporaryDirectory temp("c3d_test");
  const std::string tsv = temp.File("live_points.tsv");
  {
    std::ofstream out(tsv);
    out << LivePointsHeader(100) << LivePointLine(7, 1, 2, 3, 5, false, 3, 0.1)
        << LivePointLine(8, 1, 2, 4, 5, false, 3, 0.1);
  }
  EXPECT_EQ(TrajectoryFormatOf(tsv), TrajectoryFormat::kLivePoints);
  const MarkerTrajectories t = ReadTrajectories(tsv);
  ASSERT_EQ(t.names, std::vector<std::string>{"T5"});
  ASSERT_EQ(t.frame_numbers, (std::vector<uint64_t>{7, 8}));
  EXPECT_EQ(t.At(1, 0), Eigen::Vector3d(1, 2, 4));
  const std::string out = temp.File("out.tsv");
  EXPECT_THROW(OutputTrajectoryFormatOf(out), std::invalid_argument);
  EXPECT_THROW(WriteTrajectories(t, out), std::invalid_argument);
  EXPECT_FALSE(std::filesystem::exists(out));
}

}  // namespace
}  // namespace mocap

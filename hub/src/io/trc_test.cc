// Tests of the TRC reader and writer: exact layout, round trip, streaming, tolerance of real-world
// variations, clear errors, and the shared real motions when ../shared/data exists.
#include "io/trc.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include <gtest/gtest.h>

#include "util/temporary_directory_testing.h"

namespace mocap {
namespace {

std::string ReadAll(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

std::vector<std::string> Lines(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

MarkerTrajectories SmallMotion() {
  MarkerTrajectories motion;
  motion.rate_hz = 240.0;
  motion.names = {"LASI", "RASI", DefaultMarkerName(2)};
  for (uint64_t frame = 100; frame < 110; ++frame) {
    const size_t f = motion.AddFrame(frame);
    for (size_t m = 0; m < 3; ++m) {
      if (m == 1 && frame >= 103 && frame < 106) continue;  // a gap
      motion.At(f, m) = Eigen::Vector3d(10.0 * m + 0.12345 * frame, -1500.25 + frame, 1e-5 * m);
    }
  }
  return motion;
}

TEST(TrcTest, DefaultNames) {
  EXPECT_EQ(DefaultMarkerName(0), "M001");
  EXPECT_EQ(DefaultMarkerName(41), "M042");
  EXPECT_EQ(DefaultMarkerName(1233), "M1234");
}

TEST(TrcTest, WriterLayoutMatchesOpenSim) {
  const testing::TemporaryDirectory temp("trc_test");
  const std::string path = temp.File("layout.trc");
  WriteTrc(SmallMotion(), path);
  const std::vector<std::string> lines = Lines(ReadAll(path));
  ASSERT_EQ(lines.size(), 6u + 10u);
  EXPECT_EQ(lines[0], "PathFileType\t4\t(X/Y/Z)\tlayout.trc\t");
  EXPECT_EQ(lines[1],
            "DataRate\tCameraRate\tNumFrames\tNumMarkers\tUnits\tOrigDataRate\tOrigDataStartFrame\tOrigNumFrames\t");
  EXPECT_EQ(lines[2], "240\t240\t          10\t3\tmm\t240\t         101\t          10\t");
  EXPECT_EQ(lines[3], "Frame#\tTime\tLASI\t\t\tRASI\t\t\tM003\t\t\t");
  EXPECT_EQ(lines[4], "\t\tX1\tY1\tZ1\tX2\tY2\tZ2\tX3\tY3\tZ3\t");
  EXPECT_EQ(lines[5], "");
  // Frame 100 at 240 Hz: Frame# 101, Time 100/240; every value is followed by a tab.
  EXPECT_EQ(lines[6].substr(0, 21), "101\t0.416667\t12.34500");
  EXPECT_EQ(lines[6].back(), '\t');
  // Frame 103 has marker 2 missing: three empty cells in the middle.
  EXPECT_NE(lines[9].find("\t\t\t\t"), std::string::npos);
  EXPECT_EQ(std::count(lines[9].begin(), lines[9].end(), '\t'), 2 + 9);
}

TEST(TrcTest, RoundTrip) {
  const MarkerTrajectories motion = SmallMotion();
  const testing::TemporaryDirectory temp("trc_test");
  const std::string path = temp.File("round_trip.trc");
  WriteTrc(motion, path);
  const MarkerTrajectories read = ReadTrc(path);
  EXPECT_EQ(read.rate_hz, motion.rate_hz);
  EXPECT_EQ(read.names, motion.names);
  EXPECT_EQ(read.frame_numbers, motion.frame_numbers);
  ASSERT_EQ(read.points.size(), motion.points.size());
  for (size_t i = 0; i < motion.points.size(); ++i) {
    EXPECT_EQ(MarkerTrajectories::IsGap(read.points[i]), MarkerTrajectories::IsGap(motion.points[i])) << i;
    if (!MarkerTrajectories::IsGap(motion.points[i])) {
      EXPECT_LT((read.points[i] - motion.points[i]).norm(), 1e-5) << i;
    }
  }
}

TEST(TrcTest, StreamingWriterFlushesEveryFrame) {
  const MarkerTrajectories motion = SmallMotion();
  const testing::TemporaryDirectory temp("trc_test");
  const std::string path = temp.File("streaming.trc");
  TrcWriter writer;
  writer.Open(path, motion.names, motion.rate_hz);
  for (size_t f = 0; f < 4; ++f) {
    writer.WriteFrame(motion.frame_numbers[f], &motion.points[f * 3], 3);
  }
  // Not closed yet: a reader (or a crash) sees every frame written so far.
  const MarkerTrajectories partial = ReadTrc(path);
  EXPECT_EQ(partial.NumFrames(), 4u);
  EXPECT_EQ(partial.frame_numbers.back(), 103u);
  EXPECT_THROW(writer.WriteFrame(103, &motion.points[0], 3), std::runtime_error);
  EXPECT_THROW(writer.WriteFrame(200, &motion.points[0], 2), std::runtime_error);
  writer.Close();
  EXPECT_EQ(ReadTrc(path).NumFrames(), 4u);
  EXPECT_NE(ReadAll(path).find("\t           4\t3\tmm\t"), std::string::npos);
}

TEST(TrcTest, ReaderToleratesRealWorldVariations) {
  // CRLF, a long path line with trailing tabs, padded numbers, no X/Y/Z row, metres, a short row
  // (trailing empty cells dropped), a blank line in the data and a NaN cell.
  const std::string text =
      "PathFileType\t4\t(X/Y/Z)\tC:\\some very long\\windows path\\file.trc\t\t\t\t\r\n"
      "DataRate\tCameraRate\tNumFrames\tNumMarkers\tUnits\tOrigDataRate\t\t\r\n"
      "100.00\t100.00\t    3\t2\tm\t100.00\t\t\r\n"
      "Frame#\tTime\tA\t\t\tB\t\t\t\r\n"
      "\r\n"
      "1\t0.00\t1.0\t2.0\t3.0\t4.0\t5.0\t6.0\t\t\r\n"
      "2\t0.01\t1.5\t2.5\t3.5\r\n"
      "\r\n"
      "3\t0.02\t\t\t\t4.0\tNaN\t6.0\t\r\n"
      "4\t0.03\t0\t0.0\t-0\t0\t0\t1e-9\t\r\n";
  const MarkerTrajectories read = ParseTrc(text, "variations");
  EXPECT_EQ(read.rate_hz, 100.0);
  EXPECT_EQ(read.names, (std::vector<std::string>{"A", "B"}));
  EXPECT_EQ(read.frame_numbers, (std::vector<uint64_t>{0, 1, 2, 3}));
  EXPECT_EQ(read.At(0, 1), Eigen::Vector3d(4000.0, 5000.0, 6000.0));
  EXPECT_EQ(read.At(1, 0), Eigen::Vector3d(1500.0, 2500.0, 3500.0));
  EXPECT_FALSE(read.Has(1, 1));
  EXPECT_FALSE(read.Has(2, 0));
  EXPECT_FALSE(read.Has(2, 1));
  EXPECT_FALSE(read.Has(3, 0));  // exactly (0, 0, 0): an old-style gap
  EXPECT_TRUE(read.Has(3, 1));
  TrcReadOptions keep_zero;
  keep_zero.zero_is_gap = false;
  EXPECT_TRUE(ParseTrc(text, "variations", keep_zero).Has(3, 0));
}

TEST(TrcTest, FrameNumbersFallBackOnFrameColumnWithoutTime) {
  const std::string text =
      "PathFileType\t4\t(X/Y/Z)\tx.trc\n"
      "DataRate\tNumMarkers\tUnits\n"
      "50\t1\tmm\n"
      "Frame#\tTime\tA\t\t\n"
      "\t\tX1\tY1\tZ1\n"
      "5\t\t1\t2\t3\n"
      "7\t\t1\t2\t3\n";
  const MarkerTrajectories read = ParseTrc(text, "no-time");
  EXPECT_EQ(read.frame_numbers, (std::vector<uint64_t>{4, 6}));
}

// The header of a one-marker file: the error tests' rows follow it from line 6 on.
const std::string kOneMarkerHeader =
    "PathFileType\t4\t(X/Y/Z)\tx.trc\n"
    "DataRate\tCameraRate\tNumFrames\tNumMarkers\tUnits\n"
    "60\t60\t2\t1\tmm\n"
    "Frame#\tTime\tA\t\t\t\n"
    "\t\tX1\tY1\tZ1\t\n";

void ExpectParseError(const std::string& text, const std::string& reason) {
  try {
    ParseTrc(text, "bad.trc");
    ADD_FAILURE() << "accepted: " << text.substr(0, 400);
  } catch (const std::runtime_error& error) {
    const std::string message = error.what();
    EXPECT_EQ(message.rfind("bad.trc", 0), 0u) << message;
    EXPECT_NE(message.find(reason), std::string::npos) << message;
  }
}

TEST(TrcTest, ClearErrors) {
  ExpectParseError("", "not a TRC file");
  ExpectParseError("hello\n", "not a TRC file");
  ExpectParseError("PathFileType\t4\n", "header ends early");
  ExpectParseError("PathFileType\nDataRate\n-5\nFrame#\tTime\n", "DataRate must be positive");
  ExpectParseError("PathFileType\nDataRate\tUnits\n60\tinch\nFrame#\tTime\n", "unsupported Units");
  ExpectParseError("PathFileType\nDataRate\n60\nTime\tA\n", "must start with Frame#");
  ExpectParseError(kOneMarkerHeader + "1\t0\t1\tx\t3\t\n", "line 6: malformed coordinate \"x\"");
  ExpectParseError(kOneMarkerHeader + "1\t0\t1\t2\t3\t4\n", "more values than");
  ExpectParseError(kOneMarkerHeader + "-1\t0\t1\t2\t3\n", "Frame# must be");
  ExpectParseError(kOneMarkerHeader + "2\t0\t1\t2\t3\n1\t0\t1\t2\t3\n", "not in increasing order");
  EXPECT_THROW(ReadTrc("/nonexistent/motion.trc"), std::runtime_error);
}

TEST(TrcTest, AnEndlessLineIsRefusedNamingItInsteadOfReadWhole) {
  ExpectParseError(kOneMarkerHeader + "1\t0\t1\t2\t3" + std::string(2 << 20, 'x') + "\n", "line 6: longer than 1 MiB");
  // A row just under the bound is read whole: its error is its value's.
  ExpectParseError(kOneMarkerHeader + "1\t0\t1\t2\t3" + std::string((1 << 20) - 16, 'x') + "\n", "line 6: malformed coordinate");
  try {
    ReadTrc("/dev/zero");
    ADD_FAILURE() << "/dev/zero read as a TRC file";
  } catch (const std::runtime_error& error) {
    EXPECT_NE(std::string(error.what()).find("/dev/zero: line 1: longer than 1 MiB"), std::string::npos) << error.what();
  }
}

// The probe: a 114 KB file claiming NumMarkers 100000 cost 1.23 GB (every row was laid out
// 100000 markers wide). The width now comes from the rows: the claim only permits unnamed markers.
TEST(TrcTest, AHeaderClaimingManyMarkersCostsOnlyWhatTheRowsHold) {
  std::string text =
      "PathFileType\t4\t(X/Y/Z)\tx.trc\n"
      "DataRate\tCameraRate\tNumFrames\tNumMarkers\tUnits\n"
      "100\t100\t4000\t100000\tmm\n"
      "Frame#\tTime\tA\t\t\t\n"
      "\t\tX1\tY1\tZ1\t\n";
  size_t rows = 0;
  while (text.size() < 114 * 1024) {
    text += std::to_string(rows + 1) + "\t" + std::to_string(rows * 0.01) + "\t1\t2\t3\n";
    ++rows;
  }
  const MarkerTrajectories read = ParseTrc(text, "claims.trc");
  std::printf("114 KB TRC claiming 100000 markers: %zu frames x %zu markers = %zu points (%zu KB)\n",
              read.NumFrames(), read.NumMarkers(), read.points.size(),
              read.points.size() * sizeof(Eigen::Vector3d) / 1024);
  EXPECT_EQ(read.NumMarkers(), 1u);
  EXPECT_EQ(read.NumFrames(), rows);
  EXPECT_EQ(read.points.size(), rows);

  // Rows that widen as the file goes on: earlier rows keep their values, unnamed markers the
  // data holds get default names, the claim still bounds the width.
  const std::string widening =
      "PathFileType\t4\t(X/Y/Z)\tx.trc\n"
      "DataRate\tNumMarkers\tUnits\n"
      "100\t5\tmm\n"
      "Frame#\tTime\tA\t\t\t\n"
      "1\t0.00\t1\t2\t3\n"
      "2\t0.01\t4\t5\t6\t\t\t\t7\t8\t9\n"
      "3\t0.02\t\t\t\t1\t1\t1\n";
  const MarkerTrajectories wide = ParseTrc(widening, "widening.trc");
  EXPECT_EQ(wide.names, (std::vector<std::string>{"A", "M002", "M003"}));
  ASSERT_EQ(wide.NumFrames(), 3u);
  EXPECT_EQ(wide.At(0, 0), Eigen::Vector3d(1, 2, 3));
  EXPECT_FALSE(wide.Has(0, 2));
  EXPECT_EQ(wide.At(1, 0), Eigen::Vector3d(4, 5, 6));
  EXPECT_EQ(wide.At(1, 2), Eigen::Vector3d(7, 8, 9));
  EXPECT_EQ(wide.At(2, 1), Eigen::Vector3d(1, 1, 1));
  ExpectParseError(
      "PathFileType\t4\t(X/Y/Z)\tx.trc\nDataRate\tNumMarkers\n100\t2\nFrame#\tTime\tA\t\t\t\n"
      "1\t0\t1\t2\t3\t4\t5\t6\t7\n",
      "more values than the 2 markers");
}

// One row 100000 markers wide (its cells present) and then a million empty rows: each short row
// would be laid out 100000 markers wide. The table may not outgrow its text by more than a
// fixed factor, so this is refused at the row where it would.
TEST(TrcTest, OneWideRowCannotWidenAMillionShortOnes) {
  std::string text =
      "PathFileType\t4\t(X/Y/Z)\tx.trc\n"
      "DataRate\tNumMarkers\n100\t100000\n"
      "Frame#\tTime\tA\t\t\t\n"
      "1\t0";
  for (int m = 0; m < 100000; ++m) text += m == 99999 ? "\t1\t1\t1" : "\t\t\t";
  text += "\n";
  for (int f = 2; f < 200000; ++f) text += std::to_string(f) + "\n";
  ExpectParseError(text, "markers is more than 2 points per byte");
}

TEST(TrcTest, AFileCutInsideItsLastRowIsRefusedNamingTheRow) {
  // The probe: a TRC cut mid-row was read as a frame whose last markers were gaps, silently.
  const testing::TemporaryDirectory temp("trc_test");
  const std::string path = temp.File("cut.trc");
  WriteTrc(SmallMotion(), path);
  const std::string whole = ReadAll(path);
  const size_t last_row = whole.rfind('\n', whole.size() - 2) + 1;
  const size_t columns = 2 + 3 * 3;
  const std::string line = "line " + std::to_string(1 + std::count(whole.begin(), whole.begin() + last_row, '\n'));
  // Cut at the end of the row before: 9 whole frames, read without complaint.
  EXPECT_EQ(ParseTrc(whole.substr(0, last_row), "cut").NumFrames(), 9u);
  int refused = 0;
  for (size_t cut = last_row + 1; cut < whole.size() - 1; ++cut) {
    const std::string partial = whole.substr(0, cut);
    const size_t cells = 1 + static_cast<size_t>(std::count(partial.begin() + last_row, partial.end(), '\t'));
    if (cells >= columns) continue;  // only the last cell is cut: no length tells a shorter number
    try {
      ParseTrc(partial, "cut");
      ADD_FAILURE() << "accepted a file cut at byte " << cut << ": ..." << partial.substr(last_row);
    } catch (const std::runtime_error& e) {
      const std::string message = e.what();
      EXPECT_NE(message.find("cut: " + line + ": the file ends inside this row (" + std::to_string(cells) + " of 11 cells"),
                std::string::npos)
          << message;
      ++refused;
    }
  }
  EXPECT_GT(refused, 20);
  // The same short row with its line end is a writer leaving out empty cells: read as gaps.
  const size_t time_end = whole.find('\t', whole.find('\t', last_row) + 1);
  const std::string short_row = whole.substr(0, time_end) + "\t1\t2\t3\n";
  const MarkerTrajectories read = ParseTrc(short_row, "short");
  ASSERT_EQ(read.NumFrames(), 10u);
  EXPECT_TRUE(read.Has(9, 0));
  EXPECT_FALSE(read.Has(9, 1));
}

// Real motions recorded by commercial systems (README of ../shared/data).
TEST(TrcTest, SharedRealMotions) {
  const std::string dir = std::string(MOCAP_SHARED_DIR) + "/data/motions";
  if (!std::filesystem::exists(dir)) {
    GTEST_SKIP() << "../shared/data missing: no " << dir;
  }
  const testing::TemporaryDirectory temp("trc_test");
  struct Expected {
    const char* file;
    size_t markers;
    size_t frames;
    double rate;
    bool gaps;
  };
  for (const Expected& e : {Expected{"walk.trc", 41, 151, 60, false}, Expected{"running.trc", 41, 600, 60, true} /* L.Bicep is all (0,0,0) */,
                            Expected{"tennis_serve.trc", 39, 1092, 50, false},
                            Expected{"gaps_blank_cells.trc", 40, 464, 250, true}}) {
    SCOPED_TRACE(e.file);
    const MarkerTrajectories motion = ReadTrc(dir + "/" + e.file);
    EXPECT_EQ(motion.NumMarkers(), e.markers);
    EXPECT_EQ(motion.NumFrames(), e.frames);
    EXPECT_EQ(motion.rate_hz, e.rate);
    EXPECT_EQ(motion.frame_numbers.front(), 0u);
    EXPECT_EQ(motion.frame_numbers.back(), e.frames - 1);
    size_t gaps = 0;
    for (const Eigen::Vector3d& p : motion.points) gaps += MarkerTrajectories::IsGap(p) ? 1 : 0;
    EXPECT_EQ(gaps > 0, e.gaps);
    // Re-written files read back identically (to the written precision).
    const std::string copy = temp.File(std::string("copy_") + e.file);
    WriteTrc(motion, copy);
    const MarkerTrajectories again = ReadTrc(copy);
    ASSERT_EQ(again.points.size(), motion.points.size());
    for (size_t i = 0; i < motion.points.size(); ++i) {
      if (MarkerTrajectories::IsGap(motion.points[i])) {
        EXPECT_TRUE(MarkerTrajectories::IsGap(again.points[i]));
      } else {
        EXPECT_LT((again.points[i] - motion.points[i]).norm(), 1e-4);
      }
    }
  }
}

}  // namespace
}  // namespace mocap

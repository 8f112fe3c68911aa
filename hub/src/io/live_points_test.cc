// Live points files: what serve writes reads back as trajectories whose columns follow the
// points present at once; damaged files are refused with file:line.
#include "io/live_points.h"

#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "util/bounded_line.h"

namespace mocap {
namespace {

MarkerTrajectories Parse(const std::string& text) {
  std::istringstream in(text);
  return ParseLivePoints(in, "t.tsv").points;
}

LivePoints ParseAll(const std::string& text) {
  std::istringstream in(text);
  return ParseLivePoints(in, "t.tsv");
}

TEST(LivePoints, WrittenLinesReadBack) {
  std::string text = LivePointsHeader(120);
  text += LivePointLine(10, 1, 2, 3, 0, false, 4, 0.25);
  text += LivePointLine(10, 100, 0, 0, 17, true, 3, 0.5);
  text += LivePointLine(11, 1.5, 2, 3, 0, false, 4, 0.25);
  text += LivePointLine(11, 101, 0, 0, 17, true, 3, 0.5);
  text += LivePointLine(11, 500, 0, 0, -1, true, 2, 0.9);
  const MarkerTrajectories t = Parse(text);
  EXPECT_EQ(t.rate_hz, 120.0);
  ASSERT_EQ(t.frame_numbers, (std::vector<uint64_t>{10, 11}));
  ASSERT_EQ(t.names, (std::vector<std::string>{"M001", "P1", "P2"}));
  EXPECT_EQ(t.At(1, 0), Eigen::Vector3d(1.5, 2, 3));
  EXPECT_EQ(t.At(0, 1), Eigen::Vector3d(100, 0, 0));  // the provisional track keeps its column
  EXPECT_EQ(t.At(1, 1), Eigen::Vector3d(101, 0, 0));
  EXPECT_FALSE(t.Has(0, 2));
  EXPECT_EQ(t.At(1, 2), Eigen::Vector3d(500, 0, 0));
}

TEST(LivePoints, NamesAndTracksReadBackPerPoint) {
  std::string text = LivePointsHeader(100);
  text += LivePointLine(1, 0, 0, 0, 4, true, 2, 0.1);             // tentative serial 4, unnamed
  text += LivePointLine(1, 50, 0, 0, 2, false, 3, 0.1, "R.ASIS");  // marker 2, named
  text += LivePointLine(2, 0, 0, 1, 0, false, 3, 0.1, "L.Knee Lat");
  text += LivePointLine(2, 50, 0, 1, 2, false, 3, 0.1, "L.ASIS");  // marker 2 renamed
  text += LivePointLine(2, 90, 0, 1, -1, true, 2, 0.1);
  const LivePoints live = ParseAll(text);
  const MarkerTrajectories& t = live.points;
  // The untracked point cannot take P1 (its track was there a frame before): P2.
  ASSERT_EQ(t.names, (std::vector<std::string>{"M001", "M003", "P1", "P2"}));
  ASSERT_EQ(live.identity.names, (std::vector<std::string>{"R.ASIS", "L.Knee Lat", "L.ASIS"}));
  // Cells frame-major: frame 1 (M001, M003, P1, P2), frame 2.
  EXPECT_EQ(live.identity.track, (std::vector<int64_t>{-1, 4, 9, -1, 0, 4, -1, -1}));
  EXPECT_EQ(live.identity.name, (std::vector<int32_t>{-1, 0, -1, -1, 1, 2, -1, -1}));
  EXPECT_EQ(t.At(1, 3), Eigen::Vector3d(90, 0, 1));
  // A name that would break the row is refused when written.
  EXPECT_THROW(LivePointLine(1, 0, 0, 0, 0, false, 2, 0.1, "a\tb"), std::invalid_argument);
  EXPECT_THROW(LivePointLine(1, 0, 0, 0, 0, false, 2, 0.1, " a"), std::invalid_argument);
}

TEST(LivePoints, PoolColumnsAreReusedSoTheTableFollowsConcurrentPoints) {
  std::string text = LivePointsHeader(100);
  // 1000 short-lived provisional tracks, two at a time: the table keeps a handful of columns.
  for (uint64_t f = 0; f < 1000; ++f) {
    text += LivePointLine(f, 0, 0, f, static_cast<long long>(f + 1), true, 3, 0.1);
    text += LivePointLine(f, 9, 0, f, -1, true, 2, 0.1);
  }
  const MarkerTrajectories t = Parse(text);
  EXPECT_EQ(t.NumFrames(), 1000u);
  EXPECT_LE(t.NumMarkers(), 6u);
  size_t points = 0;
  for (size_t f = 0; f < t.NumFrames(); ++f)
    for (size_t m = 0; m < t.NumMarkers(); ++m) points += t.Has(f, m);
  EXPECT_EQ(points, 2000u);  // none lost to a shared column
}

TEST(LivePoints, DamageIsRefusedWithItsLine) {
  const std::string header = LivePointsHeader(100);
  for (const std::string& bad : {std::string("frame x y z\n"), header + "1\t2\n",
                                 header + "5\t1\t2\t3\t0\t0\t3\t0.1\n4\t1\t2\t3\t0\t0\t3\t0.1\n",
                                 header + "5\tnan\t2\t3\t0\t0\t3\t0.1\n", header + "5\t1\t2\t3\t0\t2\t3\t0.1\n",
                                 header + "5\t1\t2\t3\t-4\t0\t3\t0.1\n", header + "5\t1\t2\t3\t-4\t1\t3\t0.1\n",
                                 header + "5\t1\t2\t3\t0\t0\t3\t0.1\tA\x01B\n",
                                 header + "5\t1\t2\t3\t0\t0\t3\t0.1\t" + std::string(300, 'n') + "\n",
                                 header + "1\t1\t2\t3\t0\t0\t3\t0.1\n99999999999\t1\t2\t3\t0\t0\t3\t0.1\n",
                                 std::string("# mocap live points v1 rate_hz=-3\n"),
                                 std::string(kMaxTextLineBytes + 1, '#'), header + std::string(kMaxTextLineBytes + 1, '5')}) {
    try {
      Parse(bad);
      ADD_FAILURE() << "accepted: " << bad;
    } catch (const std::runtime_error& e) {
      EXPECT_EQ(std::string(e.what()).rfind("t.tsv:", 0), 0u) << e.what();
    }
  }
}

}  // namespace
}  // namespace mocap

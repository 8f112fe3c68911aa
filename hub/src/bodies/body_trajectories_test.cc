// Body pose files: what WriteBodyPoses writes, ParseBodyPoses reads back; anything else is
// refused with the line and the reason.
#include <cstdio>
#include <stdexcept>

#include <gtest/gtest.h>

#include "bodies/body_trajectories.h"
#include "util/special_file_testing.h"
#include "util/temporary_directory_testing.h"

namespace mocap {
namespace {

TEST(BodyPoses, RoundTrip) {
  RigidBodyDefinition body;
  body.name = "wand";
  body.markers = {{0, 0, 0}, {100, 0, 0}, {0, 80, 0}};
  BodyPoseRow row;
  row.frame_number = 41;
  BodyPose pose;
  pose.tracked = true;
  pose.orientation = Eigen::Quaterniond(Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()));
  pose.pivot = {10.5, -20.25, 1000.0};
  pose.mean_error_mm = 0.25;
  pose.markers = 3;
  row.poses = {pose};
  const testing::TemporaryDirectory temp("body_trajectories_test");
  const std::string path = temp.File("body_poses_round_trip.tsv");
  WriteBodyPoses(path, {body}, {row}, 100.0);
  const std::vector<BodyPoseRecord> read = ReadBodyPoses(path);
  ASSERT_EQ(read.size(), 1u);
  EXPECT_EQ(read[0].frame, 42u);
  EXPECT_EQ(read[0].body, "wand");
  EXPECT_TRUE(read[0].tracked);
  EXPECT_FALSE(read[0].predicted);
  EXPECT_TRUE(read[0].pivot.isApprox(pose.pivot, 1e-6));
  EXPECT_LT(read[0].orientation.angularDistance(pose.orientation), 1e-5);
  EXPECT_EQ(read[0].markers, 3u);
}

TEST(BodyPoses, AFrameWithoutAPoseHasEmptyCells) {
  RigidBodyDefinition body;
  body.name = "drone";
  BodyPoseRow row;
  row.frame_number = 7;
  BodyPose lost;  // neither fitted nor predicted
  lost.markers = 1;
  row.poses = {lost};
  const testing::TemporaryDirectory temp("body_trajectories_test");
  const std::string path = temp.File("body_poses_lost.tsv");
  WriteBodyPoses(path, {body}, {row}, 100.0);
  std::FILE* f = std::fopen(path.c_str(), "r");
  ASSERT_NE(f, nullptr);
  char line[256];
  ASSERT_NE(std::fgets(line, sizeof line, f), nullptr);  // the header
  ASSERT_NE(std::fgets(line, sizeof line, f), nullptr);
  std::fclose(f);
  EXPECT_STREQ(line, "8\t0.070000\tdrone\t0\t0\t\t\t\t\t\t\t\t\t1\n");  // no zeros, no identity quaternion
  const std::vector<BodyPoseRecord> read = ReadBodyPoses(path);
  ASSERT_EQ(read.size(), 1u);
  EXPECT_FALSE(read[0].tracked || read[0].predicted);
  EXPECT_EQ(read[0].markers, 1u);
}

TEST(BodyPoses, RefusesOtherFilesWithTheLine) {
  const std::string header = "frame\ttime_s\tbody\ttracked\tpredicted\tx\ty\tz\tqx\tqy\tqz\tqw\tmean_error_mm\tmarkers\n";
  auto reason = [](const std::string& text) {
    try {
      ParseBodyPoses(text, "poses.tsv");
    } catch (const std::runtime_error& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_NE(reason("frame\tbody\n").find("line 1: not a body pose file"), std::string::npos);
  EXPECT_NE(reason(header + "1\t0\tw\t1\t0\t1\t2\t3\t0\t0\t0\t1\t0\n").find("line 2: expected 14"), std::string::npos);
  EXPECT_NE(reason(header + "1\t0\tw\t1\t0\t1\t2\tz\t0\t0\t0\t1\t0\t3\n").find("column 8"), std::string::npos);
  EXPECT_NE(reason(header + "1\t0\tw\t1\t0\t1\t2\t3\t0\t0\t0\t2\t0\t3\n").find("unit quaternion"), std::string::npos);
  EXPECT_NE(reason(header + "1\t0\tw\t2\t0\t1\t2\t3\t0\t0\t0\t1\t0\t3\n").find("0 or 1"), std::string::npos);
  EXPECT_NE(reason("").find("empty"), std::string::npos);
  EXPECT_EQ(reason(header + "1\t0\tw\t0\t0\t0\t0\t0\t0\t0\t0\t0\t0\t0\n"), "accepted");  // an untracked row (older files)
  EXPECT_EQ(reason(header + "1\t0\tw\t0\t0\t\t\t\t\t\t\t\t\t0\n"), "accepted");  // one without a pose
  // Empty cells are no pose: a fitted row needs its numbers.
  EXPECT_NE(reason(header + "1\t0\tw\t1\t0\t\t\t\t\t\t\t\t\t0\n").find(": not a number"), std::string::npos);
}

// A pose file is read whole: a FIFO was waited on (and /dev/zero grew without end: not tried
// here, as without the check it would take all memory). Refused at once now, naming the path.
TEST(BodyPoses, ReadsOnlyRegularFiles) {
  const auto read = [](const std::string& path) { ReadBodyPoses(path); };
  const std::string fifo = testing::ErrorOfReadingAFifo(read, "poses.tsv");
  EXPECT_NE(fifo.find("poses.tsv: not a regular file (a FIFO)"), std::string::npos) << fifo;
}

}  // namespace
}  // namespace mocap

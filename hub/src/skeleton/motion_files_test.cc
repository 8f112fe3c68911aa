// The writers: BVH's hierarchy and channel counts agree with its motion lines and the skeleton;
// ASF lists every segment as a bone with its dofs and AMC one line per bone per frame; .mot reads
// back (ParseMot, MotionFromMot) to the poses written; unsolved frames repeat the last solved.
#include "skeleton/motion_files.h"

#include <cstdio>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

#include "skeleton/skeleton_sim.h"
#include "skeleton/skeleton_testing.h"

namespace mocap {
namespace {

std::string Slurp(const std::string& path) {
  std::ifstream in(path);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

size_t Count(const std::string& text, const std::string& what) {
  size_t n = 0;
  for (size_t i = text.find(what); i != std::string::npos; i = text.find(what, i + 1)) ++n;
  return n;
}

SkeletonSimulation Sim() {
  SkeletonSimOptions options;
  options.motion = SkeletonSimMotion::kGait;
  options.duration_s = 0.5;
  return SimulateSkeleton(TwentySegmentTemplate(), options);
}

TEST(MotionFiles, BvhHierarchyMatchesMotion) {
  SkeletonSimulation sim = Sim();
  sim.motion.poses[3].clear();  // unsolved: repeats frame 2
  const std::string path = ::testing::TempDir() + "/t.bvh";
  WriteBvh(sim.subject, sim.motion, path);
  const std::string text = Slurp(path);
  EXPECT_EQ(Count(text, "ROOT "), 1u);
  EXPECT_EQ(Count(text, "JOINT "), sim.subject.NumSegments() - 1);
  EXPECT_EQ(Count(text, "CHANNELS 3"), sim.subject.NumSegments() - 1);
  EXPECT_NE(text.find("Frames: " + std::to_string(sim.motion.poses.size())), std::string::npos);
  std::istringstream lines(text.substr(text.find("Frame Time:")));
  std::string line;
  std::getline(lines, line);
  std::vector<std::string> rows;
  while (std::getline(lines, line)) rows.push_back(line);
  ASSERT_EQ(rows.size(), sim.motion.poses.size());
  std::istringstream first(rows[0]);
  size_t values = 0;
  double v;
  while (first >> v) ++values;
  EXPECT_EQ(values, 6 + 3 * (sim.subject.NumSegments() - 1));
  EXPECT_EQ(rows[3], rows[2]);
}

TEST(MotionFiles, AsfAmcListEveryBone) {
  const SkeletonSimulation sim = Sim();
  const std::string asf = ::testing::TempDir() + "/t.asf", amc = ::testing::TempDir() + "/t.amc";
  WriteAsf(sim.subject, asf);
  WriteAmc(sim.subject, sim.motion, amc);
  const std::string a = Slurp(asf), m = Slurp(amc);
  for (size_t g = 1; g < sim.subject.NumSegments(); ++g) {
    EXPECT_NE(a.find("name " + sim.subject.segments[g].name + "\n"), std::string::npos);
    EXPECT_EQ(Count(m, "\n" + sim.subject.segments[g].name + " "), sim.motion.poses.size());
  }
  EXPECT_NE(a.find(":hierarchy"), std::string::npos);
  EXPECT_EQ(Count(m, "\nroot "), sim.motion.poses.size());
}

TEST(MotionFiles, MotReadsBack) {
  const SkeletonSimulation sim = Sim();
  const std::string path = ::testing::TempDir() + "/t.mot";
  WriteMot(sim.subject, sim.motion, path);
  const SkeletonMotion back = MotionFromMot(sim.subject, ReadMot(path), path);
  ASSERT_EQ(back.poses.size(), sim.motion.poses.size());
  EXPECT_NEAR(back.rate_hz, sim.motion.rate_hz, 1e-6);
  for (size_t f = 0; f < back.poses.size(); ++f)
    for (size_t k = 0; k < back.poses[f].size(); ++k) EXPECT_NEAR(back.poses[f][k], sim.motion.poses[f][k], 1e-6);
}

TEST(MotionFiles, MotRefusesBadTables) {
  EXPECT_THROW(ParseMot("a\nb\n", "x"), std::runtime_error);
  EXPECT_THROW(ParseMot("endheader\ntime a\n0 1 2\n", "x"), std::runtime_error);
  EXPECT_THROW(ParseMot("endheader\ntime a\n0 nan\n", "x"), std::runtime_error);
  const MotTable t = ParseMot("inDegrees=no\nendheader\ntime Hips_rx\n0 1\n", "x");
  EXPECT_NEAR(t.rows[0][1], 180.0 / M_PI, 1e-9);
  SkeletonMotion empty;
  empty.rate_hz = 60;
  empty.poses.resize(3);
  EXPECT_THROW(FilledPoses(empty), std::invalid_argument);
}

}  // namespace
}  // namespace mocap

// archive, convert and register as a user runs them: an archive within its bound read back by
// convert (both directions), its refusals (exit 2 for a usage error, 1 with the file named for a
// damaged archive), register's Kabsch by name and its ICP onto an OBJ recovering a known motion.
#include <cmath>
#include <cstdio>
#include <fstream>

#include <Eigen/Geometry>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "archive/trajectory_pca.h"
#include "cli/hub_process_testing.h"
#include "io/trc.h"
#include "util/temporary_directory_testing.h"

namespace mocap {
namespace {

TEST(ArchiveCli, ArchiveThenConvertBackWithinTheBound) {
  const testing::TemporaryDirectory dir("archive_cli");
  const std::string work = dir.path().string();
  ASSERT_EQ(RunHub(work, "sim motion --markers 20 --frames 700 -o m.trc").status, 0);
  const HubRun archived = RunHub(work, "archive m.trc -o m.mca --max-error-mm 0.3 --json");
  ASSERT_EQ(archived.status, 0) << archived.err;
  const nlohmann::json report = nlohmann::json::parse(archived.out);
  EXPECT_LE(report["rms_mm"].get<double>(), 0.3);
  EXPECT_GT(report["ratio"].get<double>(), 1.0);
  ASSERT_EQ(RunHub(work, "convert m.mca back.trc").status, 0);
  const MarkerTrajectories original = ReadTrc(work + "/m.trc"), back = ReadTrc(work + "/back.trc");
  EXPECT_EQ(back.names, original.names);
  EXPECT_EQ(back.frame_numbers, original.frame_numbers);
  EXPECT_LE(TrajectoryRmsError(original, back), 0.3);
  // convert writes archives too, with archive's defaults (0.5 mm).
  ASSERT_EQ(RunHub(work, "convert m.trc again.mca").status, 0);
  ASSERT_EQ(RunHub(work, "convert again.mca again.trc").status, 0);
  EXPECT_LE(TrajectoryRmsError(original, ReadTrc(work + "/again.trc")), 0.5);
}

TEST(ArchiveCli, Refusals) {
  const testing::TemporaryDirectory dir("archive_cli");
  const std::string work = dir.path().string();
  ASSERT_EQ(RunHub(work, "sim motion --markers 8 --frames 50 -o m.trc").status, 0);
  EXPECT_EQ(RunHub(work, "archive m.trc -o m.txt").status, 2);
  EXPECT_EQ(RunHub(work, "archive m.trc -o m.mca --components 300").status, 2);
  EXPECT_EQ(RunHub(work, "archive m.trc -o m.mca --max-error-mm nan").status, 2);
  std::ofstream(work + "/junk.mca") << "MOCAPMCA but not really";
  const HubRun junk = RunHub(work, "convert junk.mca out.trc");
  ExpectOneLineError(junk, "junk.mca: version");
  EXPECT_EQ(junk.status, 1);
}

TEST(RegisterCli, KabschByNameAndIcpOntoAnObj) {
  const testing::TemporaryDirectory dir("register_cli");
  const std::string work = dir.path().string();
  ASSERT_EQ(RunHub(work, "sim motion --markers 25 --frames 40 -o m.trc").status, 0);
  const HubRun named = RunHub(work, "register m.trc m.trc --source-frame 0 --target-frame 30 --json");
  ASSERT_EQ(named.status, 0) << named.err;
  EXPECT_NE(nlohmann::json::parse(named.out)["method"].get<std::string>().find("kabsch by name"), std::string::npos);
  // The markers of frame 0, turned and shifted, as the vertices of an OBJ: ICP finds the motion.
  const MarkerTrajectories motion = ReadTrc(work + "/m.trc");
  const Eigen::Matrix3d turn = Eigen::AngleAxisd(0.6, Eigen::Vector3d(0.3, 0.2, 1).normalized()).toRotationMatrix();
  const Eigen::Vector3d shift(120, -40, 300);
  {
    std::ofstream obj(work + "/cloud.obj");
    for (size_t m = 0; m < motion.NumMarkers(); ++m) {
      const Eigen::Vector3d p = turn * motion.At(0, m) + shift;
      obj << "v " << p.x() << " " << p.y() << " " << p.z() << "\n";
    }
  }
  const HubRun icp = RunHub(work, "register m.trc cloud.obj --json -o moved.trc");
  ASSERT_EQ(icp.status, 0) << icp.err;
  const nlohmann::json result = nlohmann::json::parse(icp.out);
  EXPECT_LT(result["rms_mm"].get<double>(), 0.01);  // the OBJ holds 6 significant digits
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(result["rotation"][r][c].get<double>(), turn(r, c), 1e-6);
  const MarkerTrajectories moved = ReadTrc(work + "/moved.trc");
  ASSERT_EQ(moved.NumFrames(), 1u);
  EXPECT_LT((moved.At(0, 3) - (turn * motion.At(0, 3) + shift)).norm(), 0.01);
  // Non-rigid on top: the RBF keeps an exact fit exact.
  const HubRun rbf = RunHub(work, "register m.trc cloud.obj --rbf thin-plate --json");
  ASSERT_EQ(rbf.status, 0) << rbf.err;
  EXPECT_LT(nlohmann::json::parse(rbf.out)["rms_mm"].get<double>(), 0.01);
  EXPECT_EQ(RunHub(work, "register m.trc cloud.obj --rbf cubic").status, 2);
}

}  // namespace
}  // namespace mocap

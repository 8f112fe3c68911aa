// The calibration kept with each take, as a user meets it: `reconstruct SESSION` without
// --calibration uses the session's own file and says so; a session whose camera 3 was turned
// 3 deg after its calibration (sim project --bump 3:3:0) is refused naming camera 3 with every
// camera's residual; the bumped truth calibration is accepted; --force-calibration reconstructs
// with a warning; a session without its calibration is a one-line error; `process` refuses the
// same session and the recipe's force_calibration lets it through.
#include <filesystem>
#include <fstream>
#include <regex>
#include <string>

#include <gtest/gtest.h>

#include "cli/hub_process_testing.h"
#include "util/temporary_directory_testing.h"

namespace mocap {
namespace {

namespace fs = std::filesystem;

// Each camera's "ID: MEDIAN px" in a fit line, the residuals the check printed.
double ResidualOf(const std::string& text, int camera) {
  const std::regex pattern(" " + std::to_string(camera) + ": ([0-9.]+) px");
  std::smatch match;
  if (!std::regex_search(text, match, pattern)) return -1.0;
  return std::stod(match[1]);
}

class ReconstructCalibration : public ::testing::Test {
 protected:
  void SetUp() override {
    work_ = dir_.path().string();
    ASSERT_EQ(RunHub(work_, "sim motion --markers 12 --frames 240 -o m.trc").status, 0);
    ASSERT_EQ(RunHub(work_, "sim rig --motion m.trc --cameras 6 -o rig.json").status, 0);
    HubRun run = RunHub(work_, "sim project --motion m.trc --rig rig.json -o good --noise-px 0.2 --occlusion 0.05");
    ASSERT_EQ(run.status, 0) << run.err;
    run = RunHub(work_, "sim project --motion m.trc --rig rig.json -o turned --noise-px 0.2 --occlusion 0.05 "
                        "--bump 3:3:0 --bump-from-s 0");
    ASSERT_EQ(run.status, 0) << run.err;
  }

  testing::TemporaryDirectory dir_{"reconstruct_calibration"};
  std::string work_;
};

TEST_F(ReconstructCalibration, TheSessionsOwnCalibrationIsUsedAndChecked) {
  const HubRun run = RunHub(work_, "reconstruct good -o good.trc");
  ASSERT_EQ(run.status, 0) << run.err;
  EXPECT_NE(run.out.find("good: calibration good/calibration.json (the session's own)"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("good/calibration.json: fits good:"), std::string::npos) << run.out;
  for (int camera = 1; camera <= 6; ++camera) {
    const double residual = ResidualOf(run.out, camera);
    EXPECT_GT(residual, 0.0) << camera;
    EXPECT_LT(residual, 1.0) << camera;
  }
  EXPECT_TRUE(fs::is_regular_file(work_ + "/good.trc"));
}

TEST_F(ReconstructCalibration, ACameraTurnedSinceTheCalibrationIsRefusedByName) {
  const HubRun run = RunHub(work_, "reconstruct turned -o turned.trc");
  ExpectOneLineError(run, "turned/calibration.json does not fit turned: camera 3 median ");
  EXPECT_FALSE(fs::exists(work_ + "/turned.trc"));
  const double turned = ResidualOf(run.err, 3);
  for (int camera : {1, 2, 4, 5, 6}) {
    EXPECT_LT(ResidualOf(run.err, camera), 1.0) << camera << run.err;
    EXPECT_GT(turned, 10.0 * ResidualOf(run.err, camera)) << camera << run.err;
  }
  EXPECT_EQ(run.err.find("camera 1 median"), std::string::npos) << run.err;  // only camera 3 is named

  // The calibration of the rig as it stood fits; --force-calibration goes on with a warning.
  HubRun ok = RunHub(work_, "reconstruct turned --calibration turned/truth.calibration.json -o truth.trc");
  EXPECT_EQ(ok.status, 0) << ok.err;
  EXPECT_NE(ok.out.find("turned/truth.calibration.json: fits turned:"), std::string::npos) << ok.out;
  ok = RunHub(work_, "reconstruct turned -o forced.trc --force-calibration");
  EXPECT_EQ(ok.status, 0) << ok.err;
  EXPECT_NE(ok.err.find("warning: turned/calibration.json does not fit turned: camera 3"), std::string::npos) << ok.err;
  EXPECT_TRUE(fs::is_regular_file(work_ + "/forced.trc"));
}

TEST_F(ReconstructCalibration, ASessionWithoutItsCalibrationNeedsOne) {
  fs::remove(work_ + "/good/calibration.json");
  ExpectOneLineError(RunHub(work_, "reconstruct good -o good.trc"),
                     "good: has no calibration of its own (calibration.json); give a calibration");
  EXPECT_EQ(RunHub(work_, "reconstruct good --calibration rig.json -o good.trc").status, 0);
}

TEST_F(ReconstructCalibration, ProcessRefusesTheMisfitUnlessTheRecipeForcesIt) {
  std::ofstream(work_ + "/strict.json") << R"({"format": "mocap-recipe", "version": 1, "name": "strict"})";
  std::ofstream(work_ + "/forced.json")
      << R"({"format": "mocap-recipe", "version": 1, "name": "forced", "force_calibration": true})";
  const HubRun strict = RunHub(work_, "process strict.json turned good");
  EXPECT_EQ(strict.status, 1);
  EXPECT_NE(strict.err.find("does not fit turned: camera 3 median"), std::string::npos) << strict.err;
  EXPECT_TRUE(fs::is_regular_file(work_ + "/good/processed/strict/markers.trc"));
  EXPECT_FALSE(fs::exists(work_ + "/turned/processed/strict/process.json"));
  const HubRun forced = RunHub(work_, "process forced.json turned");
  EXPECT_EQ(forced.status, 0) << forced.err;
  EXPECT_TRUE(fs::is_regular_file(work_ + "/turned/processed/forced/markers.trc"));
}

}  // namespace
}  // namespace mocap

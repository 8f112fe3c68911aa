// `process` as a user runs it: one recipe over two simulated sessions side by side gives, in each
// SESSION/processed/NAME/, the TRC `reconstruct` writes for the same options (byte for byte but
// its first line, which names the file), a C3D with the same frames and names, and process.json;
// the session's own files are untouched; a second run keeps the results unless --overwrite; a
// session that fails is named while the others are processed (exit 1); bad recipes are refused
// with the field named.
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cli/hub_process_testing.h"
#include "io/trajectory_file.h"
#include "util/temporary_directory_testing.h"

namespace mocap {
namespace {

namespace fs = std::filesystem;

std::string AfterFirstLine(const std::string& path) {
  const std::string text = ReadAll(path);
  return text.substr(text.find('\n') + 1);
}

class ProcessCli : public ::testing::Test {
 protected:
  void SetUp() override {
    work_ = dir_.path().string();
    ASSERT_EQ(RunHub(work_, "sim motion --markers 12 --frames 120 -o m.trc").status, 0);
    ASSERT_EQ(RunHub(work_, "sim rig --motion m.trc --cameras 6 -o rig.json").status, 0);
    for (const char* s : {"s1", "s2"}) {
      const HubRun run = RunHub(work_, std::string("sim project --motion m.trc --rig rig.json -o ") + s +
                                           " --noise-px 0.2 --occlusion 0.05 --seed " + (s[1] == '1' ? "1" : "2"));
      ASSERT_EQ(run.status, 0) << run.err;
    }
    std::ofstream(work_ + "/recipe.json")
        << R"({"format": "mocap-recipe", "version": 1, "name": "clean", "outputs": ["trc", "c3d"], "max_spline_gap_s": 0.1})";
  }

  testing::TemporaryDirectory dir_{"process_cli"};
  std::string work_;
};

TEST_F(ProcessCli, ARecipeOverTwoSessionsSideBySide) {
  const std::string log_before = ReadAll(work_ + "/s1/raw.mlog");
  const HubRun run = RunHub(work_, "process recipe.json s1 s2 --jobs 2");
  ASSERT_EQ(run.status, 0) << run.err;
  for (const char* s : {"s1", "s2"}) {
    const std::string out = work_ + "/" + s + "/processed/clean";
    ASSERT_TRUE(fs::is_regular_file(out + "/markers.trc")) << s;
    const HubRun same = RunHub(work_, std::string("reconstruct ") + s + " --calibration " + s +
                                          "/calibration.json -o " + s + "_direct.trc --max-spline-gap-s 0.1");
    ASSERT_EQ(same.status, 0) << same.err;
    EXPECT_EQ(AfterFirstLine(out + "/markers.trc"), AfterFirstLine(work_ + "/" + s + "_direct.trc")) << s;
    const MarkerTrajectories trc = ReadTrajectories(out + "/markers.trc"), c3d = ReadTrajectories(out + "/markers.c3d");
    EXPECT_EQ(c3d.names, trc.names);
    EXPECT_EQ(c3d.NumFrames(), trc.NumFrames());
    const nlohmann::json report = nlohmann::json::parse(ReadAll(out + "/process.json"));
    EXPECT_EQ(report["recipe"]["name"], "clean");
    EXPECT_EQ(report["outputs"], nlohmann::json({"markers.trc", "markers.c3d"}));
    EXPECT_NE(report["calibration"].get<std::string>().find(std::string(s) + "/calibration.json"), std::string::npos);
  }
  EXPECT_EQ(ReadAll(work_ + "/s1/raw.mlog"), log_before);
  // Results are kept: the same recipe again is refused per session, --overwrite replaces them.
  const HubRun again = RunHub(work_, "process recipe.json s1");
  EXPECT_EQ(again.status, 1);
  EXPECT_NE(again.err.find("already processed by recipe 'clean'"), std::string::npos) << again.err;
  EXPECT_EQ(RunHub(work_, "process recipe.json s1 --overwrite").status, 0);
}

TEST_F(ProcessCli, AFailedSessionIsNamedAndTheOthersAreProcessed) {
  fs::create_directories(work_ + "/empty");
  const HubRun run = RunHub(work_, "process recipe.json empty s2");
  EXPECT_EQ(run.status, 1);
  EXPECT_NE(run.err.find("empty: not a session (no session.json)"), std::string::npos) << run.err;
  EXPECT_NE(run.err.find("1 of 2 sessions not processed"), std::string::npos) << run.err;
  EXPECT_TRUE(fs::is_regular_file(work_ + "/s2/processed/clean/markers.trc"));
  // A session whose calibration is gone needs one in the recipe.
  fs::remove(work_ + "/s2/calibration.json");
  const HubRun lost = RunHub(work_, "process recipe.json s2 --overwrite");
  EXPECT_NE(lost.err.find("s2: has no calibration of its own (calibration.json); give a calibration"), std::string::npos)
      << lost.err;
  std::ofstream(work_ + "/with_rig.json")
      << R"({"format": "mocap-recipe", "version": 1, "name": "clean", "calibration": "rig.json"})";
  EXPECT_EQ(RunHub(work_, "process with_rig.json s2 --overwrite").status, 0);
}

TEST_F(ProcessCli, BadRecipesAreRefusedWithTheField) {
  std::ofstream(work_ + "/bad.json") << R"({"format": "mocap-recipe", "version": 1, "matcher": "magic"})";
  ExpectOneLineError(RunHub(work_, "process bad.json s1"), "bad.json: recipe field 'matcher' is 'magic'");
  std::ofstream(work_ + "/broken.json") << "{\"format\": ";
  ExpectOneLineError(RunHub(work_, "process broken.json s1"), "broken.json: not a JSON recipe");
  EXPECT_EQ(RunHub(work_, "process recipe.json s1 --jobs 0").status, 2);
  EXPECT_FALSE(fs::exists(work_ + "/s1/processed"));
}

}  // namespace
}  // namespace mocap

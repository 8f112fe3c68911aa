// End-to-end tests of the calibration commands through the mocap-hub executable: a simulated
// wand session with an L-frame, calibrate wand, calibrate world and eval-calibration without
// any alignment (and the --report page's figures); refusals and bad input end as one line on
// stderr with a non-zero status.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cli/hub_process_testing.h"
#include "util/temporary_directory_testing.h"

namespace mocap {
namespace {

class CalibrateCliTest : public ::testing::Test {
 protected:
  HubRun Hub(const std::string& args) const { return RunHub(dir_, args); }

  const testing::TemporaryDirectory temp_{"calibrate_cli"};
  const std::string dir_ = temp_.path().string();
};

// One marker waved (sim wand --single-marker-frames), then the wand shown as the scale bar:
// calibrate marker gives the rig up to a rigid motion, at the scale of the bar.
TEST_F(CalibrateCliTest, SingleMarkerWaveGivesTheRigAtTheBarsScale) {
  ASSERT_EQ(Hub("sim motion -o walk.trc --frames 120").status, 0);
  ASSERT_EQ(Hub("sim rig --motion walk.trc --cameras 8 -o rig.json").status, 0);
  const HubRun wave = Hub("sim wand --rig rig.json -o marker --frames 3300 --single-marker-frames 3000 "
                          "--noise-px 0.15 --occlusion 0.01 --seed 4");
  ASSERT_EQ(wave.status, 0) << wave.err;
  const HubRun solve = Hub("calibrate marker marker --intrinsics rig.json --scale-length 500 -o cal.json --json");
  ASSERT_EQ(solve.status, 0) << solve.err;
  const nlohmann::json report = nlohmann::json::parse(solve.out);
  EXPECT_EQ(report["cameras"].size(), 8u);
  EXPECT_GT(report["scale_frames"].get<int>(), 100);
  const HubRun eval = Hub("eval-calibration --truth rig.json --result cal.json --json");
  ASSERT_EQ(eval.status, 0) << eval.err;
  const nlohmann::json errors = nlohmann::json::parse(eval.out);
  EXPECT_LT(errors["centre_max_mm"].get<double>(), 1.0) << errors.dump();
  EXPECT_LT(errors["rotation_max_deg"].get<double>(), 0.05) << errors.dump();
  EXPECT_LT(std::abs(errors["scale_error"].get<double>()), 0.001) << errors.dump();
  ExpectOneLineError(Hub("calibrate marker marker --intrinsics rig.json --scale-length 2 -o bad.json"),
                     "--scale-length");
  EXPECT_FALSE(std::filesystem::exists(dir_ + "/bad.json"));
}

TEST_F(CalibrateCliTest, WandThenLFrameGivesTheTrueRigInItsOwnWorld) {
  ASSERT_EQ(Hub("sim motion -o walk.trc --frames 120").status, 0);
  ASSERT_EQ(Hub("sim rig --motion walk.trc --cameras 8 -o rig.json").status, 0);
  const HubRun wave = Hub("sim wand --rig rig.json -o wand --frames 1500 --noise-px 0.15 --occlusion 0.01 "
                       "--spurious 0.3 --lframe-frames 60 --seed 2");
  ASSERT_EQ(wave.status, 0) << wave.err;
  EXPECT_TRUE(std::filesystem::exists(dir_ + "/wand/calibration.json"));

  const HubRun wand =
      Hub("calibrate wand wand --intrinsics rig.json --wand-length 500 -o cal.json --json --report report");
  ASSERT_EQ(wand.status, 0) << wand.err;
  const nlohmann::json report = nlohmann::json::parse(wand.out);
  EXPECT_EQ(report["cameras"].size(), 8u);
  for (const auto& camera : report["cameras"]) {
    EXPECT_TRUE(camera["accepted"].get<bool>()) << camera.dump();
    EXPECT_NE(camera["rating"].get<std::string>(), "Poor") << camera.dump();
  }
  // --report: the page and its figures, one entry per camera as in the printed report.
  const nlohmann::json figures = nlohmann::json::parse(ReadAll(dir_ + "/report/wand_figures.json"));
  EXPECT_EQ(figures["cameras"].size(), 8u);
  EXPECT_EQ(figures["rating"], report["rating"]);
  EXPECT_NE(ReadAll(dir_ + "/report/wand_report.html").find("renderWandReport"), std::string::npos);
  EXPECT_LT(report["reprojection_rms_px"].get<double>(), 0.25);

  const HubRun world = Hub("calibrate world wand --calibration cal.json -o world.json");
  ASSERT_EQ(world.status, 0) << world.err;
  const HubRun eval = Hub("eval-calibration --truth rig.json --result world.json --no-align --json");
  ASSERT_EQ(eval.status, 0) << eval.err;
  const nlohmann::json errors = nlohmann::json::parse(eval.out);
  EXPECT_EQ(errors["cameras_matched"].get<int>(), 8);
  EXPECT_LT(errors["centre_max_mm"].get<double>(), 2.0);
  EXPECT_LT(errors["rotation_max_deg"].get<double>(), 0.03);
  EXPECT_LT(errors["reprojection_rms_px"].get<double>(), 0.25);
  // The report written into the calibration survives the world step.
  const nlohmann::json written = nlohmann::json::parse(ReadAll(dir_ + "/world.json"));
  EXPECT_EQ(written["calibration"]["method"], "wand");
  EXPECT_EQ(written["world_frame"]["method"], "lframe");
}

TEST_F(CalibrateCliTest, BadInputIsOneLineWithNonZeroStatus) {
  ExpectOneLineError(Hub("calibrate wand missing --intrinsics missing.json --wand-length 500 -o out.json"),
                     "missing.json");
  {
    std::ofstream points(dir_ + "/points.txt");
    points << "0 0 0 10 10\n1 2 3 4\n";
  }
  ExpectOneLineError(Hub("calibrate dlt points.txt --width 640 --height 480 -o out.json"), "points.txt:2");
  {
    std::ofstream mcd(dir_ + "/bad.mcd");
    mcd << "CameraCount: 3\n1\n2\n";
  }
  ExpectOneLineError(Hub("calibrate import-mcd bad.mcd -o session"), "19 values");
  ExpectOneLineError(Hub("calibrate intrinsics nothing-here -o out.json"), "nothing-here");
  ExpectOneLineError(Hub("sim wand --rig missing.json -o s --wand-length 20"), "--wand-length");
  ExpectOneLineError(Hub("calibrate wand s --wand-length 500 -o out.json"), "--intrinsics");
  ExpectOneLineError(Hub("calibrate wand s --intrinsics x.json --wand-length 500 -o out.json --apply"), "--live");
  // Live wanding needs a serve to talk to: nothing listens on port 9 of loopback.
  ExpectOneLineError(Hub("calibrate wand w --live --wand-length 500 --api 127.0.0.1:9"), "127.0.0.1:9");
  EXPECT_FALSE(std::filesystem::exists(dir_ + "/out.json"));
}

}  // namespace
}  // namespace mocap

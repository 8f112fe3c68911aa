// End-to-end tests of mocap-hub: the sim -> eval pipeline on a self-made motion, and one-line
// errors with a non-zero status for bad input.
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cli/hub_process_testing.h"
#include "io/trc.h"
#include "simcore/synthetic_motion.h"
#include "util/temporary_directory_testing.h"

namespace mocap {
namespace {

HubRun Hub(const std::string& args) { return RunHub(::testing::TempDir(), args); }

class MocapHubTest : public ::testing::Test {
 protected:
  void SetUp() override {
    SyntheticMotionOptions options;
    options.frames = 60;
    options.markers = 12;
    options.up_axis = 1;
    WriteTrc(MakeSyntheticMotion(options), dir + "/motion.trc");
  }
  const testing::TemporaryDirectory temp{"hub_cli"};
  const std::string dir = temp.path().string();
};

TEST_F(MocapHubTest, SimRigProjectAndEval) {
  HubRun rig = Hub("sim rig --motion " + dir + "/motion.trc --cameras 6 --seed 3 -o " + dir + "/rig.json --json");
  ASSERT_EQ(rig.status, 0) << rig.err;
  const nlohmann::json rig_summary = nlohmann::json::parse(rig.out);
  EXPECT_EQ(rig_summary["cameras"], 6);
  EXPECT_EQ(rig_summary["up"], "y");

  HubRun project = Hub("sim project --motion " + dir + "/motion.trc --rig " + dir + "/rig.json -o " + dir +
                    "/session --noise-px 0.1 --occlusion 0.05 --spurious 2 --drop-frames 0.01 --seed 4 --json");
  ASSERT_EQ(project.status, 0) << project.err;
  EXPECT_TRUE(project.err.empty()) << "no progress bar when stderr is not a terminal";
  const nlohmann::json summary = nlohmann::json::parse(project.out);
  EXPECT_EQ(summary["frames"], 60);
  for (const char* file : {"raw.mlog", "session.json", "truth.trc", "calibration.json", "visibility.tsv"}) {
    EXPECT_TRUE(std::filesystem::exists(dir + "/session/" + file)) << file;
  }

  // The truth against itself: perfect. Against a copy with one marker removed: missing counts.
  HubRun self = Hub("eval --truth " + dir + "/session/truth.trc --result " + dir + "/motion.trc --session " + dir +
                 "/session --json");
  ASSERT_EQ(self.status, 0) << self.err;
  const nlohmann::json perfect = nlohmann::json::parse(self.out);
  EXPECT_EQ(perfect["rmse_mm"], 0.0);
  EXPECT_EQ(perfect["ghosts_per_frame"], 0.0);
  EXPECT_EQ(perfect["missing_per_frame"], 0.0);
  EXPECT_EQ(perfect["trajectories"], 12);
  EXPECT_EQ(perfect["visibility_used"], true);

  MarkerTrajectories partial = ReadTrc(dir + "/motion.trc");
  for (size_t f = 0; f < partial.NumFrames(); ++f) partial.At(f, 3) = MarkerTrajectories::Gap();
  WriteTrc(partial, dir + "/partial.trc");
  HubRun missing = Hub("eval --truth " + dir + "/motion.trc --result " + dir + "/partial.trc --json");
  ASSERT_EQ(missing.status, 0) << missing.err;
  EXPECT_DOUBLE_EQ(nlohmann::json::parse(missing.out)["missing_per_frame"].get<double>(), 1.0);

  HubRun text = Hub("eval --truth " + dir + "/motion.trc --result " + dir + "/partial.trc");
  EXPECT_EQ(text.status, 0);
  EXPECT_NE(text.out.find("missing_per_frame"), std::string::npos);
}

TEST_F(MocapHubTest, OneLineErrors) {
  ExpectOneLineError(Hub(""), "");
  ExpectOneLineError(Hub("frobnicate"), "frobnicate");
  ExpectOneLineError(Hub("sim rig --motion /nonexistent.trc --cameras 4 -o " + dir + "/r.json"),
                     "/nonexistent.trc: cannot open");
  ExpectOneLineError(Hub("sim rig --motion " + dir + "/motion.trc -o " + dir + "/r.json"), "--cameras");
  ExpectOneLineError(Hub("sim rig --motion " + dir + "/motion.trc --cameras 1 -o " + dir + "/r.json"),
                     "--cameras must be");
  ExpectOneLineError(Hub("sim rig --motion " + dir + "/motion.trc --cameras 4 --up w -o " + dir + "/r.json"),
                     "--up");
  ExpectOneLineError(Hub("sim rig --motion " + dir + "/motion.trc --cameras abc -o " + dir + "/r.json"), "abc");
  std::ofstream(dir + "/broken.trc") << "PathFileType\t4\nDataRate\n60\nFrame#\tTime\tA\t\t\n1\t0\t1\tx\t3\n";
  ExpectOneLineError(Hub("eval --truth " + dir + "/motion.trc --result " + dir + "/broken.trc"),
                     "broken.trc: line 5: malformed coordinate");
  ExpectOneLineError(Hub("sim project --motion " + dir + "/motion.trc --rig " + dir + "/nope.json -o " + dir +
                         "/s"),
                     "nope.json: cannot open");
  ASSERT_EQ(Hub("sim rig --motion " + dir + "/motion.trc --cameras 4 -o " + dir + "/r.json").status, 0);
  ExpectOneLineError(Hub("sim project --motion " + dir + "/motion.trc --rig " + dir + "/r.json -o " + dir +
                         "/s --occlusion 2"),
                     "--occlusion must be");
  ExpectOneLineError(Hub("eval --truth " + dir + "/motion.trc --result " + dir + "/motion.trc --session " + dir),
                     "no visibility.tsv");
}

// The exit status policy (cli/commands.h): 0 ok, 1 runtime or input error, 2 usage error.
TEST_F(MocapHubTest, ExitStatusSaysWhoseMistakeItWas) {
  const std::string motion = " --motion " + dir + "/motion.trc";
  EXPECT_EQ(Hub("--help").status, 0);
  EXPECT_EQ(Hub("eval --help").status, 0);
  // Usage: no command, an unknown command or option, a missing or malformed or out-of-range value.
  EXPECT_EQ(Hub("").status, 2);
  EXPECT_EQ(Hub("frobnicate").status, 2);
  EXPECT_EQ(Hub("sim rig" + motion + " --cameras 4 --frobnicate -o " + dir + "/r.json").status, 2);
  EXPECT_EQ(Hub("sim rig" + motion + " -o " + dir + "/r.json").status, 2);
  EXPECT_EQ(Hub("sim rig" + motion + " --cameras abc -o " + dir + "/r.json").status, 2);
  EXPECT_EQ(Hub("sim rig" + motion + " --cameras 1 -o " + dir + "/r.json").status, 2);
  EXPECT_EQ(Hub("sim rig" + motion + " --cameras 4 --up w -o " + dir + "/r.json").status, 2);
  EXPECT_EQ(Hub("bench --cameras 1").status, 2);
  EXPECT_EQ(Hub("--log-level loud sim rig" + motion + " --cameras 4 -o " + dir + "/r.json").status, 2);
  // Input: files that cannot be read or are not what they should be.
  EXPECT_EQ(Hub("sim rig --motion /nonexistent.trc --cameras 4 -o " + dir + "/r.json").status, 1);
  EXPECT_EQ(Hub("reconstruct " + dir + " --calibration " + dir + "/motion.trc -o " + dir + "/o.trc").status, 1);
  EXPECT_EQ(Hub("sim project" + motion + " --rig " + dir + "/motion.trc -o " + dir + "/s").status, 1);
  // --log-level goes before or after the command name; "off" silences diagnostics, never results.
  const HubRun quiet = Hub("sim rig" + motion + " --cameras 4 -o " + dir + "/r.json --log-level off");
  EXPECT_EQ(quiet.status, 0) << quiet.err;
  EXPECT_NE(quiet.out.find("4 cameras"), std::string::npos) << quiet.out;
  EXPECT_EQ(Hub("--log-level debug sim rig" + motion + " --cameras 4 -o " + dir + "/r.json").status, 0);
}

// record: numbers that would make it run forever or wait without end are usage errors, and an
// existing recording is never overwritten.
TEST_F(MocapHubTest, RecordRefusesEndlessNumbersAndExistingSessions) {
  ASSERT_EQ(Hub("sim rig --motion " + dir + "/motion.trc --cameras 4 -o " + dir + "/rec_rig.json").status, 0);
  // (--insecure-dev-wire: no node will talk; the wire keys are not what this test is about)
  const std::string record =
      "record --insecure-dev-wire --listen 127.0.0.1:0 --calibration " + dir + "/rec_rig.json -o " + dir + "/rec";
  for (const char* bad : {"--frames -1", "--frames 0", "--duration 0", "--duration nan", "--duration -1",
                          "--deadline-ms nan", "--deadline-ms -1", "--epoch-ns -1", "--rate 0", "--rate inf"})
    EXPECT_EQ(Hub(record + " " + bad).status, 2) << bad;
  ASSERT_EQ(Hub(record + " --duration 0.2").status, 0);
  const std::string log = dir + "/rec/raw.mlog";
  const auto size = std::filesystem::file_size(log);
  const HubRun again = Hub(record + " --duration 0.2");
  EXPECT_EQ(again.status, 1);
  EXPECT_NE(again.err.find("holds a recorded session already"), std::string::npos) << again.err;
  EXPECT_EQ(std::filesystem::file_size(log), size);
}

// serve and reconstruct: out-of-range numbers are usage errors before anything starts.
TEST_F(MocapHubTest, ServeAndReconstructRefuseOutOfRangeNumbers) {
  ASSERT_EQ(Hub("sim rig --motion " + dir + "/motion.trc --cameras 4 -o " + dir + "/opt_rig.json").status, 0);
  const std::string serve = "serve --insecure-dev-wire --listen 127.0.0.1:0 --api 127.0.0.1:0 --web-root off "
                            "--sessions-dir " + dir + "/opt_sessions --calibration " + dir + "/opt_rig.json";
  for (const char* bad : {"--busy-poll-us -1", "--busy-poll-us nan", "--busy-poll-us 1e9", "--deadline-ms 0",
                          "--deadline-ms nan", "--deadline-ms -1", "--rate 0", "--rate inf", "--epoch-ns -1",
                          "--announce nonsense",
                          "--contested-gate-factor -1", "--contested-gate-factor nan"})
    EXPECT_EQ(Hub(serve + " " + bad).status, 2) << bad;
  // reconstruct: a real session, so that only the option is wrong.
  ASSERT_EQ(Hub("sim project --motion " + dir + "/motion.trc --rig " + dir + "/opt_rig.json -o " + dir +
                "/opt_session").status, 0);
  const std::string reconstruct = "reconstruct " + dir + "/opt_session --calibration " + dir + "/opt_rig.json -o " +
                                  dir + "/opt.trc";
  for (const char* bad : {"--contested-gate-factor -1", "--contested-gate-factor nan"}) {
    const HubRun run = Hub(reconstruct + " " + bad);
    EXPECT_EQ(run.status, 2) << bad;
    EXPECT_NE(run.err.find("contested_gate_factor"), std::string::npos) << run.err;
  }
}

TEST_F(MocapHubTest, SimMotionWritesASyntheticTrc) {
  const HubRun run = Hub("sim motion --markers 7 --frames 30 --rate 240 --up x -o " + dir + "/synthetic.trc");
  ASSERT_EQ(run.status, 0) << run.err;
  const MarkerTrajectories motion = ReadTrc(dir + "/synthetic.trc");
  EXPECT_EQ(motion.NumMarkers(), 7u);
  EXPECT_EQ(motion.NumFrames(), 30u);
  EXPECT_EQ(motion.rate_hz, 240.0);
  EXPECT_EQ(motion.names[6], "M007");
  ExpectOneLineError(Hub("sim motion --markers 0 -o " + dir + "/x.trc"), "markers must be");
}

TEST_F(MocapHubTest, SimRenderWritesFramesPerCamera) {
  ASSERT_EQ(Hub("sim rig --motion " + dir + "/motion.trc --cameras 3 --width 640 --height 400 -o " + dir +
                "/rig.json").status,
            0);
  const HubRun run = Hub("sim render --motion " + dir + "/motion.trc --rig " + dir + "/rig.json -o " + dir +
                         "/frames --occlusion 0.1 --reflections 2 --seed 9 --json");
  ASSERT_EQ(run.status, 0) << run.err;
  const nlohmann::json summary = nlohmann::json::parse(run.out);
  EXPECT_EQ(summary["cameras"], 3);
  EXPECT_EQ(summary["frames"], 60);
  EXPECT_EQ(summary["camera_frames"], 180);
  // Mostly dark frames: far below the 256 kB of a raw 640x400 frame per camera frame.
  EXPECT_LT(summary["bytes"].get<double>() / 180.0, 25600.0);
  for (const char* file : {"cam1/frames.mcf", "cam2/frames.mcf", "cam3/frames.mcf", "truth.trc", "calibration.json",
                           "visibility.tsv"}) {
    EXPECT_TRUE(std::filesystem::exists(dir + "/frames/" + file)) << file;
  }
  ExpectOneLineError(Hub("sim render --motion " + dir + "/motion.trc --rig " + dir + "/rig.json -o " + dir +
                         "/f2 --gain 0"),
                     "--gain must be");
  ExpectOneLineError(Hub("sim render --motion " + dir + "/motion.trc --rig " + dir + "/nope.json -o " + dir + "/f3"),
                     "nope.json: cannot open");
}

TEST_F(MocapHubTest, HelpSucceeds) {
  const HubRun help = Hub("--help");
  EXPECT_EQ(help.status, 0);
  EXPECT_NE(help.out.find("sim"), std::string::npos);
  EXPECT_NE(help.out.find("eval"), std::string::npos);
  const HubRun sim_help = Hub("sim project --help");
  EXPECT_EQ(sim_help.status, 0);
  EXPECT_NE(sim_help.out.find("--occlusion-frames"), std::string::npos);
}

}  // namespace
}  // namespace mocap

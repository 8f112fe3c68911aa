// `calibrate marker SESSION --intrinsics CAL --scale-length MM -o CAL`: extrinsics from one
// marker waved through the volume, the scale from a bar of known length shown after it
// (calib/single_marker_calibration.h). The world is the reference camera's; `calibrate world`
// levels it on an L-frame or the floor.
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "calib/session_frames.h"
#include "calib/single_marker_calibration.h"
#include "calib/single_marker_report.h"
#include "io/calibration_json.h"
#include "cli/commands.h"
#include "util/json_file.h"
#include "util/log.h"

namespace mocap {
namespace {

struct CalibrateMarkerArgs {
  std::string session;
  std::string intrinsics;
  std::string output;
  bool json = false;
  SingleMarkerOptions options;
};

void RunCalibrateMarker(const CalibrateMarkerArgs& args) {
  CheckOptions(args.options);
  const Rig intrinsics = LoadRigJson(args.intrinsics);
  std::vector<std::string> warnings;
  const std::vector<FrameSet> frames = LoadSessionFrames(args.session, &warnings);
  for (const std::string& warning : warnings) log::Warn("{}", warning);
  const SingleMarkerResult result = CalibrateSingleMarker(frames, intrinsics, args.options);
  const nlohmann::json report = SingleMarkerReportJson(result, args.options, args.session);
  const nlohmann::json document = SingleMarkerCalibrationDocument(result, report);
  WriteJsonFile(document, args.output);
  if (args.json) {
    std::printf("%s\n", report.dump().c_str());
    return;
  }
  for (const SingleMarkerCamera& c : result.cameras) {
    std::printf("camera %u: %zu views, %zu used, rms %.3f px%s\n", c.id, c.views, c.used, c.rms_px,
                c.joined_through == 0 ? " (reference)" : "");
  }
  std::printf("calibrate marker: %zu frames used of %zu; scale from %zu bar frames (length RMS %.3f mm) -> %s\n",
              result.frames_used, result.frames_selected, result.scale_frames, result.scale_length_rms_mm,
              args.output.c_str());
}

}  // namespace

void AddCalibrateMarkerCommand(CLI::App& app) {
  CLI::App& calibrate = CommandGroup(app, "calibrate");
  CLI::App* command = calibrate.add_subcommand(
      "marker", "Extrinsics from one marker waved through the volume, scale from a bar of known length");
  auto args = std::make_shared<CalibrateMarkerArgs>();
  command->add_option("session", args->session, "Session directory: the marker waved, then the scale bar shown")
      ->required();
  command->add_option("--intrinsics", args->intrinsics, "Calibration JSON giving each camera's intrinsics")
      ->required();
  command->add_option("--scale-length", args->options.scale_length_mm,
                      "Distance between the scale bar's two markers, mm (frames with exactly two blobs)")
      ->required();
  command->add_option("-o,--output", args->output, "Calibration JSON to write")->required();
  command->add_option("--threads", args->options.num_threads, "Solver threads")
      ->check(CLI::Range(1, 64))
      ->capture_default_str();
  command->add_flag("--json", args->json, "Print the report as one JSON object on stdout");
  command->callback([args] { RunCalibrateMarker(*args); });
}

}  // namespace mocap

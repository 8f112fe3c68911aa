// Seed 000's files: `calibrate import-tsai` (Tsai camera blocks -> calibration JSON) and
// `calibrate import-mcd` (.mcd recordings -> session directory).
#include <cstdio>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "calib/mcd.h"
#include "calib/tsai.h"
#include "cli/calibrate_helpers.h"
#include "cli/commands.h"
#include "ingest/session.h"
#include "io/calibration_json.h"
#include "util/json_file.h"

namespace mocap {
namespace {

Rig RigFromTsai(const std::vector<TsaiCamera>& cameras, int width, int height, nlohmann::json* fits) {
  Rig rig;
  for (size_t i = 0; i < cameras.size(); ++i) {
    const TsaiConversion conversion = CameraFromTsai(cameras[i], static_cast<uint32_t>(i + 1), width, height);
    rig.cameras.push_back(conversion.camera);
    fits->push_back({{"id", i + 1}, {"lens_fit_max_error_px", conversion.max_error_px}});
  }
  return rig;
}

struct ImportTsaiArgs {
  std::string input;
  std::string output;
  int width = 0;
  int height = 0;
};

void RunImportTsai(const ImportTsaiArgs& args) {
  if (args.width < 0 || args.height < 0) throw UsageError("--width and --height must be positive");
  nlohmann::json fits = nlohmann::json::array();
  const Rig rig = RigFromTsai(ReadTsaiFile(args.input), args.width, args.height, &fits);
  nlohmann::json document = RigToJson(rig);
  document["calibration"] = {{"method", "tsai import"}, {"source", args.input}, {"cameras", fits}};
  WriteJsonFile(document, args.output);
  for (const auto& fit : fits) {
    std::printf("camera %d: Tsai kappa1 fitted by OpenCV k1 k2 k3 within %.4f px\n", fit["id"].get<int>(),
                fit["lens_fit_max_error_px"].get<double>());
  }
  std::printf("import-tsai: %zu cameras -> %s\n", rig.cameras.size(), args.output.c_str());
}

struct ImportMcdArgs {
  std::string input;
  std::string output;
  int width = 0;
  int height = 0;
  double rate_hz = 25.0;
};

void RunImportMcd(const ImportMcdArgs& args) {
  if (args.width < 0 || args.height < 0) throw UsageError("--width and --height must be positive");
  if (!(args.rate_hz > 0.0 && args.rate_hz <= 10000.0)) throw UsageError("--rate must be in (0, 10000]");
  const McdRecording recording = ReadMcd(args.input);
  nlohmann::json fits = nlohmann::json::array();
  const Rig rig = RigFromTsai(recording.cameras, args.width, args.height, &fits);
  SessionInfo info;
  info.rate_hz = args.rate_hz;
  info.epoch_ns = 0;
  info.free_run = true;  // seed 000's webcams were polled by the server, not triggered
  for (const Camera& camera : rig.cameras) info.camera_ids.push_back(camera.id);
  info.source = "import-mcd";
  info.extra["import"] = {{"mcd", args.input}, {"tsai_fits", fits}};
  SessionWriter writer;
  writer.Create(args.output, info, SessionWriter::Existing::kReplace);  // a conversion: its source stays
  uint64_t blobs = 0;
  for (const FrameSet& set : recording.frames) {
    for (CameraFrame frame : set.cameras) {
      const Camera& camera = *rig.Find(frame.camera_id);
      frame.width = static_cast<uint32_t>(camera.intrinsics.width);
      frame.height = static_cast<uint32_t>(camera.intrinsics.height);
      frame.trigger_time_ns = static_cast<uint64_t>(std::llround(static_cast<double>(set.frame_number) * 1e9 / args.rate_hz));
      frame.capture_time_ns = frame.trigger_time_ns;
      blobs += frame.blobs.size();
      writer.Write(frame);
    }
  }
  writer.Finish();
  SaveRigJson(rig, (std::filesystem::path(args.output) / info.calibration).string());
  std::printf("import-mcd: %zu cameras, %zu frames, %llu marks -> session %s (calibration.json from the Tsai "
              "blocks)\n",
              rig.cameras.size(), recording.frames.size(), static_cast<unsigned long long>(blobs),
              args.output.c_str());
}

// ---- eval-calibration -----------------------------------------------------------------------

}  // namespace

void AddCalibrateImportTsaiCommand(CLI::App& app) {
  CLI::App& calibrate = CommandGroup(app, "calibrate");
  CLI::App* command =
      calibrate.add_subcommand("import-tsai", "Convert seed 000 Tsai camera blocks (19 values) to calibration JSON");
  auto args = std::make_shared<ImportTsaiArgs>();
  command->add_option("input", args->input, "File of Tsai blocks separated by blank lines")->required();
  command->add_option("-o,--output", args->output, "Calibration JSON to write")->required();
  command->add_option("--width", args->width, "Image width, px (default: Nfx)");
  command->add_option("--height", args->height, "Image height, px (default: 3/4 of the width)");
  command->callback([args] { RunImportTsai(*args); });
}

void AddCalibrateImportMcdCommand(CLI::App& app) {
  CLI::App& calibrate = CommandGroup(app, "calibrate");
  CLI::App* command =
      calibrate.add_subcommand("import-mcd", "Convert a seed 000 .mcd recording into a session directory");
  auto args = std::make_shared<ImportMcdArgs>();
  command->add_option("input", args->input, ".mcd file")->required();
  command->add_option("-o,--output", args->output, "Session directory to write")->required();
  command->add_option("--rate", args->rate_hz, "Frame rate of the recording, Hz")->capture_default_str();
  command->add_option("--width", args->width, "Image width, px (default: Nfx)");
  command->add_option("--height", args->height, "Image height, px (default: 3/4 of the width)");
  command->callback([args] { RunImportMcd(*args); });
}

}  // namespace mocap

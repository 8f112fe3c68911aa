// Seed 000's square target: `calibrate target` (the printable page as SVG and its points as
// JSON), `calibrate target-points` (control points found in a camera image, for `calibrate
// dlt` or Willson's Tsai tool) and `sim target-image` (the target rendered through a rig camera).
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <stdexcept>
#include <string>

#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "calib/calibration_target.h"
#include "calib/target_detection.h"
#include "cli/commands.h"
#include "io/calibration_json.h"
#include "sim/target_render.h"
#include "util/json_file.h"

namespace mocap {
namespace {

struct TargetArgs {
  std::string output;
  std::string json;
  CalibrationTargetLayout layout;
};

void RunCalibrateTarget(const TargetArgs& args) {
  CheckOptions(args.layout);
  const std::string json = args.json.empty() ? std::filesystem::path(args.output).replace_extension(".json").string()
                                             : args.json;
  if (json == args.output) throw UsageError("--json must name another file than -o");
  {
    std::ofstream out(args.output);
    out << TargetSvg(args.layout);
    out.close();
    if (!out) throw std::runtime_error(args.output + ": cannot be written");
  }
  WriteJsonFile(TargetToJson(args.layout), json);
  std::printf("calibrate target: %s (%.0f x %.0f mm page, fold in the middle), %d points in %s\n", args.output.c_str(),
              args.layout.PageWidthMm(), args.layout.PageHeightMm(), args.layout.NumPoints(), json.c_str());
}

struct TargetPointsArgs {
  std::string image;
  std::string target;
  std::string output;
  bool json = false;
  TargetDetectionOptions options;
};

void RunCalibrateTargetPoints(const TargetPointsArgs& args) {
  CheckOptions(args.options);
  const CalibrationTargetLayout layout = ReadTargetJson(args.target);
  const cv::Mat image = cv::imread(args.image, cv::IMREAD_GRAYSCALE);
  if (image.empty()) throw std::runtime_error(args.image + ": not an image OpenCV can read");
  TargetDetection detection;
  try {
    detection = DetectTargetPoints(image, layout, args.options);
  } catch (const std::runtime_error& error) {
    throw std::runtime_error(args.image + ": " + error.what());
  }
  WriteControlPoints(detection.points, args.output,
                     "control points of " + args.target + " found in " + args.image + " (mocap-hub calibrate target-points)");
  if (args.json) {
    std::printf("%s\n", nlohmann::json({{"points", detection.points.size()},
                                        {"wall_points", detection.wall_points},
                                        {"floor_points", detection.floor_points},
                                        {"squares_seen", detection.squares_seen},
                                        {"output", args.output}})
                            .dump()
                            .c_str());
  } else {
    std::printf("calibrate target-points: %zu of %d points (wall %d, floor %d; %d dark squares seen); wrote %s\n",
                detection.points.size(), layout.NumPoints(), detection.wall_points, detection.floor_points,
                detection.squares_seen, args.output.c_str());
  }
}

struct TargetImageArgs {
  std::string target;
  std::string rig;
  uint32_t camera_id = 1;
  std::string output;
  TargetRenderOptions options;
};

void RunSimTargetImage(const TargetImageArgs& args) {
  CheckOptions(args.options);
  const CalibrationTargetLayout layout = ReadTargetJson(args.target);
  const Rig rig = LoadRigJson(args.rig);
  const Camera* camera = rig.Find(args.camera_id);
  if (camera == nullptr) throw UsageError(args.rig + " has no camera " + std::to_string(args.camera_id));
  const cv::Mat image = RenderTarget(layout, *camera, args.options);
  if (!cv::imwrite(args.output, image)) throw std::runtime_error(args.output + ": cannot be written");
  std::printf("sim target-image: camera %u, %dx%d, wrote %s\n", camera->id, image.cols, image.rows,
              args.output.c_str());
}

}  // namespace

void AddCalibrateTargetCommands(CLI::App& app) {
  CLI::App& calibrate = CommandGroup(app, "calibrate");
  {
    CLI::App* command = calibrate.add_subcommand("target", "Write seed 000's printable square target (SVG + JSON)");
    auto args = std::make_shared<TargetArgs>();
    CalibrationTargetLayout& l = args->layout;
    command->add_option("-o,--output", args->output, "SVG page to write")->required();
    command->add_option("--json", args->json, "Point coordinates to write (default: the SVG's name with .json)");
    command->add_option("--rows", l.rows, "Rows of squares per face")->capture_default_str();
    command->add_option("--cols", l.cols, "Squares along the fold")->capture_default_str();
    command->add_option("--square-mm", l.square_mm, "Side of a square, mm")->check(FiniteRange(4, 500))->capture_default_str();
    command->add_option("--gap-mm", l.gap_mm, "Gap between squares, mm")->check(FiniteRange(0, 500))->capture_default_str();
    command->add_option("--edge-mm", l.edge_mm, "Page edge to the squares, mm")->check(FiniteRange(0, 500))->capture_default_str();
    command->add_option("--fold-mm", l.fold_mm, "Fold line to the first row, mm")->check(FiniteRange(0, 500))->capture_default_str();
    command->callback([args] { RunCalibrateTarget(*args); });
  }
  {
    CLI::App* command = calibrate.add_subcommand(
        "target-points", "Find the target's corners in a camera image (Harris): control points for calibrate dlt");
    auto args = std::make_shared<TargetPointsArgs>();
    command->add_option("image", args->image, "Camera image (PNG, JPEG, PGM...)")->required();
    command->add_option("--target", args->target, "Target JSON written by calibrate target")->required();
    command->add_option("-o,--output", args->output, "Control points to write ('x y z u v' lines)")->required();
    command->add_option("--min-square-px", args->options.min_square_px, "Smallest square side, px")
        ->check(FiniteRange(3, 10000))
        ->capture_default_str();
    command->add_flag("--json", args->json, "Print a JSON summary on stdout");
    command->callback([args] { RunCalibrateTargetPoints(*args); });
  }
}

void AddSimTargetImageCommand(CLI::App& app) {
  CLI::App& sim = CommandGroup(app, "sim");
  CLI::App* command = sim.add_subcommand("target-image", "Render the calibration target through one rig camera");
  auto args = std::make_shared<TargetImageArgs>();
  command->add_option("--target", args->target, "Target JSON written by calibrate target")->required();
  command->add_option("--rig", args->rig, "Rig / calibration JSON")->required();
  command->add_option("--camera", args->camera_id, "Camera id")->capture_default_str();
  command->add_option("-o,--output", args->output, "Image to write (PNG)")->required();
  command->add_option("--blur-px", args->options.blur_sigma_px, "Lens blur sigma, px")->capture_default_str();
  command->add_option("--noise", args->options.noise, "Sensor noise sigma, grey levels")->capture_default_str();
  command->add_option("--seed", args->options.seed, "Noise seed")->capture_default_str();
  command->callback([args] { RunSimTargetImage(*args); });
}

}  // namespace mocap

// One camera at a time: `calibrate intrinsics` (checkerboard or ChArUco images, OpenCV) and
// `calibrate dlt` (11-parameter DLT from known control points, seed 000).
#include <cstdio>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include "calib/dlt.h"
#include "calib/intrinsics.h"
#include "calib/world_frame.h"
#include "cli/calibrate_helpers.h"
#include "cli/commands.h"
#include "io/calibration_json.h"
#include "util/json_file.h"

namespace mocap {
namespace {

struct CalibrateIntrinsicsArgs {
  std::vector<std::string> images;
  std::string output;
  std::string target_name = "checkerboard";
  uint32_t id = 1;
  bool free_k3 = false;
  bool json = false;
  CalibrationTarget target;
  IntrinsicsOptions options;
};

void RunCalibrateIntrinsics(CalibrateIntrinsicsArgs args) {
  args.target.type = TargetTypeFromName(args.target_name);
  args.options.fix_k3 = !args.free_k3;
  CheckOptions(args.target);
  CheckOptions(args.options);
  const std::vector<std::string> files = ExpandImagePaths(args.images);
  if (files.empty()) throw std::runtime_error("no image files given");
  const std::vector<cv::Mat> images = ReadGreyImages(files);
  const IntrinsicsResult result = CalibrateIntrinsics(images, files, args.target, args.options);
  Rig rig;
  Camera camera;
  camera.id = args.id;
  camera.intrinsics = result.intrinsics;
  rig.cameras.push_back(camera);
  nlohmann::json document = RigToJson(rig);
  nlohmann::json views = nlohmann::json::array();
  int used = 0;
  for (const IntrinsicsView& view : result.views) {
    views.push_back({{"image", view.name}, {"used", view.used}, {"corners", view.corners}, {"reason", view.reason}});
    used += view.used ? 1 : 0;
  }
  document["calibration"] = {{"method", "intrinsics"},
                             {"target", TargetTypeName(args.target.type)},
                             {"rms_px", result.rms_px},
                             {"images", views}};
  document["cameras"][0]["note"] =
      "intrinsics only: rotation is identity and translation zero until calibrate wand solves them";
  WriteJsonFile(document, args.output);
  if (args.json) {
    std::printf("%s\n", document["calibration"].dump().c_str());
    return;
  }
  const CameraIntrinsics& in = result.intrinsics;
  std::printf("calibrate intrinsics: target found in %d of %zu images, RMS %.3f px\n", used, files.size(),
              result.rms_px);
  std::printf("fx %.2f fy %.2f cx %.2f cy %.2f  k1 %.5f k2 %.5f p1 %.6f p2 %.6f k3 %.5f -> %s\n", in.fx, in.fy, in.cx,
              in.cy, in.distortion[0], in.distortion[1], in.distortion[2], in.distortion[3], in.distortion[4],
              args.output.c_str());
  for (const IntrinsicsView& view : result.views) {
    if (!view.used) std::printf("  skipped %s: %s\n", view.name.c_str(), view.reason.c_str());
  }
}

// ---- calibrate dlt --------------------------------------------------------------------------

struct CalibrateDltArgs {
  std::string points;
  std::string output;
  bool no_refine = false;
  bool json = false;
  DltOptions options;
};

void RunCalibrateDlt(CalibrateDltArgs args) {
  args.options.refine = !args.no_refine;
  CheckOptions(args.options);
  const std::vector<ControlPoint> points = ReadControlPoints(args.points);
  const DltResult result = CalibrateDlt(points, args.options);
  Rig rig;
  rig.cameras.push_back(result.camera);
  nlohmann::json document = RigToJson(rig);
  document["cameras"][0]["reprojection_rms_px"] = result.camera_rms_px;
  document["calibration"] = {{"method", "dlt"},
                             {"control_points", points.size()},
                             {"dlt_parameters", result.parameters},
                             {"dlt_rms_px", result.linear_rms_px},
                             {"skew_px", result.skew_px},
                             {"camera_rms_px", result.camera_rms_px}};
  WriteJsonFile(document, args.output);
  if (args.json) {
    std::printf("%s\n", document["calibration"].dump().c_str());
    return;
  }
  const Eigen::Vector3d centre = result.camera.CenterInWorld();
  std::printf("calibrate dlt: %zu control points; 11-parameter DLT RMS %.3f px (skew %.2f px dropped); camera RMS "
              "%.3f px; centre (%.1f, %.1f, %.1f) mm; fx %.1f fy %.1f -> %s\n",
              points.size(), result.linear_rms_px, result.skew_px, result.camera_rms_px, centre.x(), centre.y(),
              centre.z(), result.camera.intrinsics.fx, result.camera.intrinsics.fy, args.output.c_str());
}

// ---- calibrate import-tsai / import-mcd -----------------------------------------------------

}  // namespace

void AddCalibrateIntrinsicsCommand(CLI::App& app) {
  CLI::App& calibrate = CommandGroup(app, "calibrate");
  CLI::App* command = calibrate.add_subcommand("intrinsics", "Intrinsics from checkerboard or ChArUco images");
  auto args = std::make_shared<CalibrateIntrinsicsArgs>();
  CalibrationTarget& t = args->target;
  command->add_option("images", args->images, "Image files or directories of them")->required();
  command->add_option("-o,--output", args->output, "Calibration JSON to write")->required();
  command->add_option("--target", args->target_name, "checkerboard or charuco")->capture_default_str();
  command->add_option("--squares-x", t.squares_x, "Squares across the board")->capture_default_str();
  command->add_option("--squares-y", t.squares_y, "Squares down the board")->capture_default_str();
  command->add_option("--square-mm", t.square_mm, "Square side, mm")->capture_default_str();
  command->add_option("--marker-mm", t.marker_mm, "ChArUco marker side, mm")->capture_default_str();
  command->add_option("--dictionary", t.dictionary, "ChArUco dictionary (4x4_50, 5x5_100, 6x6_250, ...)")
      ->capture_default_str();
  command->add_option("--id", args->id, "Camera id to write")->capture_default_str();
  command->add_option("--min-views", args->options.min_views, "Images that must show the board")
      ->capture_default_str();
  command->add_flag("--free-k3", args->free_k3, "Also estimate k3 (needs many well-spread views)");
  command->add_flag("--json", args->json, "Print a JSON summary on stdout");
  command->callback([args] { RunCalibrateIntrinsics(*args); });
}

void AddCalibrateDltCommand(CLI::App& app) {
  CLI::App& calibrate = CommandGroup(app, "calibrate");
  CLI::App* command =
      calibrate.add_subcommand("dlt", "One camera from known 3D control points by the 11-parameter DLT");
  auto args = std::make_shared<CalibrateDltArgs>();
  command->add_option("points", args->points, "Control points, one 'x y z u v' per line (mm, px)")->required();
  command->add_option("-o,--output", args->output, "Calibration JSON to write")->required();
  command->add_option("--width", args->options.width, "Image width, px")->required();
  command->add_option("--height", args->options.height, "Image height, px")->required();
  command->add_option("--id", args->options.camera_id, "Camera id to write")->capture_default_str();
  command->add_flag("--refine-distortion", args->options.refine_distortion,
                    "Also fit k1 k2 p1 p2 (needs points across the whole image)");
  command->add_flag("--no-refine", args->no_refine, "Keep the linear solution");
  command->add_flag("--json", args->json, "Print a JSON summary on stdout");
  command->callback([args] { RunCalibrateDlt(*args); });
}

}  // namespace mocap

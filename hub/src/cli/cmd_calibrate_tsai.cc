// `calibrate tsai` (seed 000 section 3.2: one camera from known control points by Tsai's
// method, coplanar or not) and `calibrate merge` (a rig from per-camera calibrations: one JSON
// per camera, each in the calibration target's coordinates, which are the rig's common world).
#include <cstdio>
#include <memory>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include "calib/dlt.h"
#include "calib/tsai_calibration.h"
#include "cli/commands.h"
#include "io/calibration_json.h"
#include "util/json_file.h"

namespace mocap {
namespace {

struct CalibrateTsaiArgs {
  std::string points;
  std::string output;
  bool no_refine = false;
  bool fix_centre = false;
  bool json = false;
  TsaiCalibrationOptions options;
};

nlohmann::json TsaiBlockJson(const TsaiCamera& t) {
  return {{"Ncx", t.ncx}, {"Nfx", t.nfx}, {"dx", t.dx}, {"dy", t.dy}, {"dpx", t.dpx}, {"dpy", t.dpy},
          {"Cx", t.cx},   {"Cy", t.cy},   {"sx", t.sx}, {"f", t.f},   {"kappa1", t.kappa1},
          {"Tx", t.tx},   {"Ty", t.ty},   {"Tz", t.tz}, {"Rx", t.rx}, {"Ry", t.ry}, {"Rz", t.rz}};
}

void RunCalibrateTsai(CalibrateTsaiArgs args) {
  args.options.refine = !args.no_refine;
  args.options.refine_centre = !args.fix_centre;
  CheckOptions(args.options);
  const std::vector<ControlPoint> points = ReadControlPoints(args.points);
  TsaiCalibrationResult result;
  try {
    result = CalibrateTsai(points, args.options);
  } catch (const std::invalid_argument& error) {
    throw std::runtime_error(args.points + ": " + error.what());
  }
  Rig rig;
  rig.cameras.push_back(result.camera.camera);
  nlohmann::json document = RigToJson(rig);
  document["cameras"][0]["reprojection_rms_px"] = result.rms_px;
  document["calibration"] = {{"method", "tsai"},
                             {"control_points", points.size()},
                             {"coplanar", result.coplanar},
                             {"linear_rms_px", result.linear_rms_px},
                             {"tsai_rms_px", result.rms_px},
                             {"opencv_fit_max_px", result.camera.max_error_px},
                             {"tsai", TsaiBlockJson(result.tsai)}};
  WriteJsonFile(document, args.output);
  if (args.json) {
    std::printf("%s\n", document["calibration"].dump().c_str());
    return;
  }
  const Eigen::Vector3d centre = result.camera.camera.CenterInWorld();
  std::printf("calibrate tsai: %zu %scontrol points; linear RMS %.3f px, Tsai RMS %.3f px; f %.4f mm, kappa1 %.6g "
              "1/mm^2, sx %.5f, centre (%.1f, %.1f, %.1f) mm; OpenCV lens fit %.4f px -> %s\n",
              points.size(), result.coplanar ? "coplanar " : "", result.linear_rms_px, result.rms_px, result.tsai.f,
              result.tsai.kappa1, result.tsai.sx, centre.x(), centre.y(), centre.z(), result.camera.max_error_px,
              args.output.c_str());
}

struct CalibrateMergeArgs {
  std::vector<std::string> inputs;
  std::string output;
};

// Cameras keep every field their file wrote (reprojection figures included); the ids must
// differ, since they name the nodes.
void RunCalibrateMerge(const CalibrateMergeArgs& args) {
  nlohmann::json cameras = nlohmann::json::array();
  std::set<uint32_t> ids;
  nlohmann::json sources = nlohmann::json::array();
  for (const std::string& path : args.inputs) {
    const Rig rig = LoadRigJson(path);  // validates every camera
    const nlohmann::json document = ReadJsonFile(path);
    for (size_t c = 0; c < rig.cameras.size(); ++c) {
      const uint32_t id = rig.cameras[c].id;
      if (!ids.insert(id).second)
        throw std::runtime_error(path + ": camera " + std::to_string(id) +
                                 " is already in an earlier file; give each camera its own id (--id when calibrating)");
      cameras.push_back(document["cameras"][c]);
    }
    sources.push_back({{"file", path}, {"cameras", rig.cameras.size()}});
  }
  nlohmann::json merged = {{"units", "mm"}, {"cameras", cameras}, {"calibration", {{"method", "merge"}, {"sources", sources}}}};
  RigFromJson(merged, args.output);  // the merged rig reads back
  WriteJsonFile(merged, args.output);
  std::printf("calibrate merge: %zu cameras from %zu files -> %s\n", cameras.size(), args.inputs.size(),
              args.output.c_str());
}

}  // namespace

void AddCalibrateTsaiCommands(CLI::App& app) {
  CLI::App& calibrate = CommandGroup(app, "calibrate");
  CLI::App* command = calibrate.add_subcommand(
      "tsai", "One camera from known 3D control points by Tsai's method (coplanar or not, kappa1)");
  auto args = std::make_shared<CalibrateTsaiArgs>();
  TsaiCalibrationOptions& o = args->options;
  command->add_option("points", args->points, "Control points, one 'x y z u v' per line (mm, px)")->required();
  command->add_option("-o,--output", args->output, "Calibration JSON to write")->required();
  command->add_option("--width", o.width, "Image width, px")->required();
  command->add_option("--height", o.height, "Image height, px")->required();
  command->add_option("--id", o.camera_id, "Camera id to write")->capture_default_str();
  command->add_option("--pixel-mm", o.pixel_mm, "Sensor cell size, mm (dx = dy)")->capture_default_str();
  command->add_option("--sx", o.sx, "x scale factor for coplanar points (not estimable from them)")
      ->capture_default_str();
  command->add_flag("--fix-centre", args->fix_centre, "Keep the image centre at the middle of the image");
  command->add_flag("--no-refine", args->no_refine, "Keep the linear solution (no kappa1)");
  command->add_flag("--json", args->json, "Print a JSON summary on stdout");
  command->callback([args] { RunCalibrateTsai(*args); });

  CLI::App* merge = calibrate.add_subcommand(
      "merge", "One rig from per-camera calibrations made in the same target coordinates");
  auto merge_args = std::make_shared<CalibrateMergeArgs>();
  merge->add_option("calibrations", merge_args->inputs, "Calibration JSON files (one or more cameras each)")
      ->required();
  merge->add_option("-o,--output", merge_args->output, "Rig calibration JSON to write")->required();
  merge->callback([merge_args] { RunCalibrateMerge(*merge_args); });
}

}  // namespace mocap

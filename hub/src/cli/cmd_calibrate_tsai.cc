// `calibrate tsai` (seed 000 section 3.2: one camera from known control points by Tsai's
// method, coplanar or not) and `calibrate merge` (a rig from per-camera calibrations: one JSON
// per camera, each in the calibration target's coordinates, which are the rig's common world).
#include <cmath>
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
  std::vector<std::string> points;  // one file per view
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
  std::vector<std::vector<ControlPoint>> views;
  size_t count = 0;
  for (const std::string& path : args.points) {
    views.push_back(ReadControlPoints(path));
    count += views.back().size();
  }
  TsaiCalibrationResult result;
  try {
    result = CalibrateTsaiViews(views, args.options);
  } catch (const std::invalid_argument& error) {
    throw std::runtime_error(args.points[0] + (views.size() > 1 ? " and the other views" : "") + ": " + error.what());
  }
  if (!result.kappa1_determined) std::fprintf(stderr, "calibrate tsai: warning: %s\n", result.kappa1_note.c_str());
  Rig rig;
  rig.cameras.push_back(result.camera.camera);
  nlohmann::json document = RigToJson(rig);
  document["cameras"][0]["reprojection_rms_px"] = result.rms_px;
  document["calibration"] = {{"method", "tsai"},
                             {"control_points", count},
                             {"views", views.size()},
                             {"coplanar", result.coplanar},
                             {"kappa1_determined", result.kappa1_determined},
                             {"kappa1_sigma", std::isfinite(result.kappa1_sigma) ? nlohmann::json(result.kappa1_sigma)
                                                                                 : nlohmann::json(nullptr)},
                             {"kappa1_corner_sigma_px", std::isfinite(result.kappa1_corner_sigma_px)
                                                            ? nlohmann::json(result.kappa1_corner_sigma_px)
                                                            : nlohmann::json(nullptr)},
                             {"coverage", result.coverage},
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
  std::printf("calibrate tsai: %zu %scontrol points in %zu view(s); linear RMS %.3f px, Tsai RMS %.3f px; f %.4f mm, "
              "kappa1 %.6g 1/mm^2 (sigma %.2g, %.2g px at the image corner%s), sx %.5f, centre (%.1f, %.1f, %.1f) mm "
              "(first view); OpenCV lens fit %.4f px -> %s\n",
              count, result.coplanar ? "coplanar " : "", views.size(), result.linear_rms_px, result.rms_px,
              result.tsai.f, result.tsai.kappa1, result.kappa1_sigma, result.kappa1_corner_sigma_px,
              result.kappa1_determined ? "" : ": undetermined", result.tsai.sx, centre.x(), centre.y(), centre.z(),
              result.camera.max_error_px, args.output.c_str());
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
  command->add_option("points", args->points,
                      "Control points, one 'x y z u v' per line (mm, px); one file per view of the target by this "
                      "camera (the intrinsics shared, the pose written is the first view's)")
      ->required();
  command->add_option("-o,--output", args->output, "Calibration JSON to write")->required();
  command->add_option("--width", o.width, "Image width, px")->required();
  command->add_option("--height", o.height, "Image height, px")->required();
  command->add_option("--id", o.camera_id, "Camera id to write")->capture_default_str();
  command->add_option("--pixel-mm", o.pixel_mm, "Sensor cell size, mm (dx = dy)")->capture_default_str();
  command->add_option("--sx", o.sx, "x scale factor for coplanar points (not estimable from them)")
      ->capture_default_str();
  command->add_flag("--fix-centre", args->fix_centre, "Keep the image centre at the middle of the image");
  command->add_flag("--no-refine", args->no_refine, "Keep the linear solution (no kappa1)");
  command->add_option("--max-kappa1-sigma-px", o.max_kappa1_corner_sigma_px,
                      "kappa1 counts as determined when one standard deviation of it moves the image corner by at "
                      "most this, px")
      ->capture_default_str();
  command->add_flag("--require-kappa1", o.require_kappa1,
                    "Refuse (instead of warning) when the points do not determine kappa1");
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

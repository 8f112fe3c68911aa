// `eval-calibration`: camera centre, rotation, scale and focal errors of a calibration against
// a truth rig, after a rigid alignment.
#include <cstdio>
#include <map>
#include <memory>
#include <string>

#include <nlohmann/json.hpp>

#include "cli/calibrate_helpers.h"
#include "cli/commands.h"
#include "eval/calibration_eval.h"
#include "io/calibration_json.h"

namespace mocap {
namespace {

struct EvalCalibrationArgs {
  std::string truth;
  std::string result;
  bool no_align = false;
  bool json = false;
};

void RunEvalCalibration(const EvalCalibrationArgs& args) {
  const Rig truth = LoadRigJson(args.truth);
  const Rig result = LoadRigJson(args.result);
  const std::map<uint32_t, double> reported = ReadReportedReprojectionRms(args.result);
  CalibrationEvalOptions options;
  options.align = !args.no_align;
  const CalibrationEval eval = EvaluateCalibration(truth, result, reported, options);
  auto number_or_null = [](double v) { return std::isnan(v) ? nlohmann::json(nullptr) : nlohmann::json(v); };
  if (args.json) {
    nlohmann::json cameras = nlohmann::json::array();
    for (const auto& c : eval.cameras) {
      cameras.push_back({{"id", c.id},
                         {"centre_error_mm", c.centre_error_mm},
                         {"rotation_error_deg", c.rotation_error_deg},
                         {"focal_error_percent", c.focal_error_percent},
                         {"reprojection_rms_px", number_or_null(c.reprojection_rms_px)}});
    }
    std::printf("%s\n", nlohmann::json({{"aligned", eval.aligned},
                                        {"cameras_matched", eval.cameras.size()},
                                        {"cameras_missing", eval.missing},
                                        {"centre_rms_mm", eval.centre_rms_mm},
                                        {"centre_max_mm", eval.centre_max_mm},
                                        {"rotation_rms_deg", eval.rotation_rms_deg},
                                        {"rotation_max_deg", eval.rotation_max_deg},
                                        {"scale_error", eval.scale_error},
                                        {"reprojection_rms_px", number_or_null(eval.reprojection_rms_px)},
                                        {"cameras", cameras}})
                            .dump()
                            .c_str());
    return;
  }
  std::printf("%6s %12s %14s %10s %8s\n", "camera", "centre_mm", "rotation_deg", "focal_%", "rms_px");
  for (const auto& c : eval.cameras) {
    std::printf("%6u %12.3f %14.5f %+10.4f %8.3f\n", c.id, c.centre_error_mm, c.rotation_error_deg,
                c.focal_error_percent, c.reprojection_rms_px);
  }
  std::printf("%zu cameras%s: centre error rms %.3f mm max %.3f mm; rotation error rms %.5f deg max %.5f deg; "
              "scale error %+.4f %%; reprojection RMS %.3f px\n",
              eval.cameras.size(), eval.aligned ? " (rigidly aligned)" : " (world frames compared as they are)",
              eval.centre_rms_mm, eval.centre_max_mm, eval.rotation_rms_deg, eval.rotation_max_deg,
              100.0 * eval.scale_error, eval.reprojection_rms_px);
  for (uint32_t id : eval.missing) std::printf("camera %u of the truth is missing from the result\n", id);
}

}  // namespace

void AddEvalCalibrationCommand(CLI::App& app) {
  CLI::App* command = app.add_subcommand("eval-calibration", "Accuracy of a calibration against a truth rig");
  auto args = std::make_shared<EvalCalibrationArgs>();
  command->add_option("--truth", args->truth, "Truth rig (calibration JSON)")->required();
  command->add_option("--result", args->result, "Calibration to evaluate")->required();
  command->add_flag("--no-align", args->no_align, "Compare world frames as they are (no rigid alignment)");
  command->add_flag("--json", args->json, "Print one JSON object on stdout");
  command->callback([args] { RunEvalCalibration(*args); });
}

}  // namespace mocap

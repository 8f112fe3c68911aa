// `eval-calibration`: camera centre, rotation, scale and focal errors of a calibration against
// a truth rig, after a rigid alignment; with several --result files, the repeatability of
// repeated calibrations (eval/calibration_repeatability.h), against the truth when given.
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli/calibrate_helpers.h"
#include "cli/commands.h"
#include "eval/calibration_eval.h"
#include "eval/calibration_repeatability.h"
#include "io/calibration_json.h"

namespace mocap {
namespace {

struct EvalCalibrationArgs {
  std::string truth;
  std::vector<std::string> results;
  bool no_align = false;
  bool json = false;
};

nlohmann::json Vector(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }

void RunRepeatability(const EvalCalibrationArgs& args) {
  std::vector<Rig> calibrations;
  for (const std::string& path : args.results) calibrations.push_back(LoadRigJson(path));
  std::optional<Rig> truth;
  if (!args.truth.empty()) truth = LoadRigJson(args.truth);
  const CalibrationRepeatability r = EvaluateRepeatability(calibrations, truth ? &*truth : nullptr, !args.no_align);
  auto number_or_null = [](double v) { return std::isnan(v) ? nlohmann::json(nullptr) : nlohmann::json(v); };
  if (args.json) {
    nlohmann::json cameras = nlohmann::json::array();
    for (const CameraRepeatability& c : r.cameras) {
      cameras.push_back({{"id", c.id},
                         {"calibrations", c.calibrations},
                         {"centre_mean_mm", Vector(c.centre_mean_mm)},
                         {"centre_std_mm", Vector(c.centre_std_mm)},
                         {"centre_spread_mm", c.centre_spread_mm},
                         {"euler_mean_deg", Vector(c.euler_mean_deg)},
                         {"rotation_std_deg", Vector(c.rotation_std_deg)},
                         {"rotation_spread_deg", c.rotation_spread_deg},
                         {"centre_bias_mm", number_or_null(c.centre_bias_mm)},
                         {"rotation_bias_deg", number_or_null(c.rotation_bias_deg)}});
    }
    std::printf("%s\n", nlohmann::json({{"calibrations", r.calibrations},
                                        {"aligned", r.aligned},
                                        {"against_truth", r.against_truth},
                                        {"centre_spread_max_mm", r.centre_spread_max_mm},
                                        {"rotation_spread_max_deg", r.rotation_spread_max_deg},
                                        {"cameras", cameras}})
                            .dump()
                            .c_str());
    return;
  }
  std::printf("%6s %5s %28s %22s %10s %24s %10s", "camera", "n", "centre mean mm (x y z)", "centre std mm",
              "spread_mm", "rotation std deg (x y z)", "spread_deg");
  std::printf(r.against_truth ? " %10s %10s\n" : "\n", "bias_mm", "bias_deg");
  for (const CameraRepeatability& c : r.cameras) {
    std::printf("%6u %5zu %9.2f %9.2f %8.2f %7.3f %7.3f %6.3f %10.3f %8.4f %7.4f %7.4f %10.4f", c.id, c.calibrations,
                c.centre_mean_mm.x(), c.centre_mean_mm.y(), c.centre_mean_mm.z(), c.centre_std_mm.x(),
                c.centre_std_mm.y(), c.centre_std_mm.z(), c.centre_spread_mm, c.rotation_std_deg.x(),
                c.rotation_std_deg.y(), c.rotation_std_deg.z(), c.rotation_spread_deg);
    if (r.against_truth) std::printf(" %10.3f %10.4f", c.centre_bias_mm, c.rotation_bias_deg);
    std::printf("\n");
  }
  std::printf("%zu calibrations%s: worst centre spread %.3f mm, worst rotation spread %.4f deg\n", r.calibrations,
              r.aligned ? (r.against_truth ? " (each aligned onto the truth)" : " (each aligned onto the first)")
                        : " (world frames compared as they are)",
              r.centre_spread_max_mm, r.rotation_spread_max_deg);
}

void RunEvalCalibration(const EvalCalibrationArgs& args) {
  if (args.results.size() > 1) return RunRepeatability(args);
  if (args.truth.empty())
    throw std::runtime_error("--truth is required with one --result (several --result files give their repeatability)");
  const Rig truth = LoadRigJson(args.truth);
  const Rig result = LoadRigJson(args.results.front());
  const std::map<uint32_t, double> reported = ReadReportedReprojectionRms(args.results.front());
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
  command->add_option("--truth", args->truth,
                      "Truth rig (calibration JSON); optional with several --result files");
  command->add_option("--result", args->results,
                      "Calibration to evaluate; several (repeat the option or list them): each camera's mean and "
                      "standard deviation of centre and rotation over them")
      ->required();
  command->add_flag("--no-align", args->no_align, "Compare world frames as they are (no rigid alignment)");
  command->add_flag("--json", args->json, "Print one JSON object on stdout");
  command->callback([args] { RunEvalCalibration(*args); });
}

}  // namespace mocap

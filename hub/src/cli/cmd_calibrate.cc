// Calibration commands: `sim wand` (a simulated wand session), `calibrate wand` (extrinsics by
// bundle adjustment), `eval-calibration` (accuracy against a truth rig). Each validates its
// inputs and throws a one-line reason; main() prints it and exits non-zero.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "calib/session_frames.h"
#include "calib/wand_calibration.h"
#include "calib/world_frame.h"
#include "cli/commands.h"
#include "cli/progress.h"
#include "eval/calibration_eval.h"
#include "io/calibration_json.h"
#include "sim/project_session.h"
#include "sim/wand.h"

namespace mocap {
namespace {

constexpr const char* kSimDescription = "Simulator: virtual rigs, projected sessions with realistic faults";
constexpr const char* kCalibrateDescription =
    "Camera calibration: wand extrinsics, world frame, intrinsics, DLT and seed-format imports";

int ParseUpAxisName(const std::string& up) {
  if (up == "auto") return -1;
  if (up == "x" || up == "X") return 0;
  if (up == "y" || up == "Y") return 1;
  if (up == "z" || up == "Z") return 2;
  throw std::invalid_argument("--up must be x, y, z or auto");
}

// "x,y,z;x,y,z;..." in mm.
std::vector<Eigen::Vector3d> ParsePointList(const std::string& text, const std::string& option) {
  std::vector<Eigen::Vector3d> points;
  size_t start = 0;
  while (start <= text.size()) {
    const size_t end = std::min(text.find(';', start), text.size());
    const std::string item = text.substr(start, end - start);
    if (!item.empty()) {
      double x, y, z;
      char tail;
      if (std::sscanf(item.c_str(), " %lf , %lf , %lf %c", &x, &y, &z, &tail) != 3 ||
          !std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z)) {
        throw std::invalid_argument(option + ": '" + item + "' is not a point 'x,y,z' (mm)");
      }
      points.emplace_back(x, y, z);
    }
    start = end + 1;
  }
  if (points.empty()) throw std::invalid_argument(option + ": no points given");
  return points;
}

void WriteJsonFile(const nlohmann::json& document, const std::string& path) {
  const std::filesystem::path parent = std::filesystem::path(path).parent_path();
  std::error_code ignored;
  if (!parent.empty()) std::filesystem::create_directories(parent, ignored);
  std::ofstream out(path);
  if (!out) throw std::runtime_error(path + ": cannot write");
  out << document.dump(2) << "\n";
  if (!out) throw std::runtime_error(path + ": write failed");
}

// ---- sim wand -------------------------------------------------------------------------------

struct SimWandArgs {
  std::string rig;
  std::string output;
  std::string up = "auto";
  std::string lframe;
  bool json = false;
  WandMotionOptions wand;
  ProjectOptions project;
};

void RunSimWand(SimWandArgs args) {
  args.project.Check();
  args.wand.up_axis = ParseUpAxisName(args.up);
  if (args.wand.lframe_frames > 0) {
    args.wand.lframe_markers = args.lframe.empty() ? DefaultLFrame(args.wand.up_axis < 0 ? 2 : args.wand.up_axis)
                                                   : ParsePointList(args.lframe, "--lframe");
  }
  args.wand.Check();
  const Rig rig = LoadRigJson(args.rig);
  args.project.seed = args.wand.seed;
  const MarkerTrajectories motion = MakeWandMotion(rig, args.wand);
  ProgressBar progress("sim wand", motion.NumFrames());
  const ProjectSessionStats stats =
      ProjectSession(motion, rig, args.project, args.output, [&](size_t done, size_t) { progress.Update(done); });
  progress.Finish();
  if (args.json) {
    std::printf("%s\n", nlohmann::json({{"session", args.output},
                                        {"frames", stats.frames},
                                        {"camera_frames", stats.camera_frames},
                                        {"blobs", stats.blobs},
                                        {"wand_length_mm", args.wand.wand_length_mm},
                                        {"lframe_frames", args.wand.lframe_frames}})
                            .dump()
                            .c_str());
  } else {
    std::printf("%s: %llu frames of a %.1f mm wand%s, %llu blobs; truth rig in %s/calibration.json\n",
                args.output.c_str(), static_cast<unsigned long long>(stats.frames), args.wand.wand_length_mm,
                args.wand.lframe_frames > 0 ? " then an L-frame" : "", static_cast<unsigned long long>(stats.blobs),
                args.output.c_str());
  }
}

// ---- calibrate wand -------------------------------------------------------------------------

struct CalibrateWandArgs {
  std::string session;
  std::string intrinsics;
  std::string output;
  double wand_length_mm = 0.0;
  double middle_marker_mm = 0.0;
  std::string refine = "none";
  int reference_camera_id = -1;
  bool allow_partial = false;
  bool json = false;
  WandCalibrationOptions options;
};

nlohmann::json LengthJson(const LengthErrorStats& s) {
  return {{"frames", s.count},      {"mean_mm", s.mean_mm},         {"rms_mm", s.rms_mm},
          {"median_abs_mm", s.median_abs_mm}, {"p95_abs_mm", s.p95_abs_mm}, {"max_abs_mm", s.max_abs_mm}};
}

nlohmann::json ReportJson(const WandCalibrationResult& result, const WandGeometry& wand) {
  nlohmann::json cameras = nlohmann::json::array();
  for (const CameraCalibrationReport& c : result.cameras) {
    cameras.push_back({{"id", c.id},
                       {"accepted", c.accepted},
                       {"reason", c.reason},
                       {"views_selected", c.views_selected},
                       {"views_used", c.views_used},
                       {"reprojection_rms_px", c.reprojection_rms_px},
                       {"coverage", c.coverage},
                       {"wand_length_error", LengthJson(c.wand_length)}});
  }
  return {{"method", "wand"},
          {"wand_length_mm", wand.LengthMm()},
          {"wand_markers", wand.MarkerCount()},
          {"reference_camera", result.reference_camera_id},
          {"frames", result.frames_in},
          {"frames_selected", result.frames_selected},
          {"frames_used", result.frames_used},
          {"reprojection_rms_px", result.reprojection_rms_px},
          {"reprojection_rms_definition", "per image coordinate"},
          {"wand_length_error", LengthJson(result.wand_length)},
          {"solver_iterations", result.solver_iterations},
          {"seconds", result.select_seconds + result.initialize_seconds + result.bundle_seconds},
          {"cameras", cameras}};
}

void PrintReport(const WandCalibrationResult& result) {
  size_t accepted = 0;
  for (const auto& c : result.cameras) accepted += c.accepted ? 1 : 0;
  std::printf("calibrate wand: %zu/%zu cameras accepted, reference camera %u, %zu of %zu frames used "
              "(%zu selected), %d solver iterations, %.1f s\n",
              accepted, result.cameras.size(), result.reference_camera_id, result.frames_used, result.frames_in,
              result.frames_selected, result.solver_iterations,
              result.select_seconds + result.initialize_seconds + result.bundle_seconds);
  std::printf("%6s %7s %7s %8s %9s %12s %12s  %s\n", "camera", "views", "used", "rms_px", "coverage",
              "len_rms_mm", "len_p95_mm", "status");
  for (const auto& c : result.cameras) {
    std::printf("%6u %7zu %7zu %8.3f %8.0f%% %12.3f %12.3f  %s\n", c.id, c.views_selected, c.views_used,
                c.reprojection_rms_px, 100.0 * c.coverage, c.wand_length.rms_mm, c.wand_length.p95_abs_mm,
                c.accepted ? "ok" : ("REFUSED: " + c.reason).c_str());
  }
  const LengthErrorStats& w = result.wand_length;
  std::printf("reprojection RMS %.3f px (per coordinate); wand length error over %zu frames: mean %+.3f mm, "
              "rms %.3f mm, median |e| %.3f mm, p95 %.3f mm, max %.3f mm\n",
              result.reprojection_rms_px, w.count, w.mean_mm, w.rms_mm, w.median_abs_mm, w.p95_abs_mm, w.max_abs_mm);
}

void RunCalibrateWand(CalibrateWandArgs args) {
  const WandGeometry wand = args.middle_marker_mm > 0.0
                                ? WandGeometry::ThreeMarker(args.wand_length_mm, args.middle_marker_mm)
                                : WandGeometry::TwoMarker(args.wand_length_mm);
  wand.Check();
  args.options.bundle.refine_intrinsics = IntrinsicsRefinementFromName(args.refine);
  const Rig intrinsics = LoadRigJson(args.intrinsics);
  if (args.reference_camera_id >= 0) {
    const Camera* reference = intrinsics.Find(static_cast<uint32_t>(args.reference_camera_id));
    if (reference == nullptr) {
      throw std::invalid_argument(fmt::format("--reference-camera {}: no such camera in {}", args.reference_camera_id,
                                              args.intrinsics));
    }
    args.options.initialization.reference_camera = static_cast<int>(reference - intrinsics.cameras.data());
  }
  args.options.Check();
  const std::vector<FrameSet> frames = LoadSessionFrames(args.session);
  const WandCalibrationResult result = CalibrateWand(frames, intrinsics, wand, args.options);
  const nlohmann::json report = ReportJson(result, wand);
  if (args.json) {
    std::printf("%s\n", report.dump().c_str());
  } else {
    PrintReport(result);
  }
  if (!result.AllAccepted() && !args.allow_partial) {
    std::string reasons;
    for (const auto& c : result.cameras) {
      if (!c.accepted) reasons += fmt::format("{}camera {}: {}", reasons.empty() ? "" : "; ", c.id, c.reason);
    }
    throw std::runtime_error("calibration refused, nothing written (--allow-partial writes the accepted cameras): " +
                             reasons);
  }
  nlohmann::json document = RigToJson(result.rig);
  for (auto& camera : document["cameras"]) {
    for (const auto& c : result.cameras) {
      if (c.id == camera["id"].get<uint32_t>()) {
        camera["reprojection_rms_px"] = c.reprojection_rms_px;
        camera["wand_views"] = c.views_used;
        camera["coverage"] = c.coverage;
      }
    }
  }
  document["calibration"] = report;
  WriteJsonFile(document, args.output);
}

// ---- eval-calibration -----------------------------------------------------------------------

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

void AddSimWandCommand(CLI::App& app) {
  CLI::App& sim = CommandGroup(app, "sim", kSimDescription);
  CLI::App* command = sim.add_subcommand("wand", "Wave a calibration wand through a rig's volume into a session");
  auto args = std::make_shared<SimWandArgs>();
  WandMotionOptions& w = args->wand;
  ProjectOptions& p = args->project;
  command->add_option("--rig", args->rig, "Rig / calibration JSON (the truth)")->required();
  command->add_option("-o,--output", args->output, "Session directory to write")->required();
  command->add_option("--wand-length", w.wand_length_mm, "Distance between the wand's end markers, mm")
      ->capture_default_str();
  command->add_option("--middle-marker", w.middle_marker_mm,
                      "Third marker this far from the first end, mm (0 = two-marker wand)")
      ->capture_default_str();
  command->add_option("--frames", w.frames, "Frames of waving")->capture_default_str();
  command->add_option("--rate", w.rate_hz, "Frame rate, Hz")->capture_default_str();
  command->add_option("--speed", w.speed_mm_s, "Mean hand speed, mm/s")->capture_default_str();
  command->add_option("--min-cameras", w.min_cameras,
                      "Wave where at least this many cameras see (0 = half the rig)")
      ->capture_default_str();
  command->add_option("--up", args->up, "Vertical axis: x, y, z or auto (from the cameras)")->capture_default_str();
  command->add_option("--lframe-frames", w.lframe_frames, "Static L-frame frames after the waving")
      ->capture_default_str();
  command->add_option("--lframe", args->lframe,
                      "L-frame markers in world mm, 'x,y,z;x,y,z;...' (default: 4-marker L on the floor)");
  command->add_option("--noise-px", p.noise_px, "Centroid noise sigma, px")->capture_default_str();
  command->add_option("--occlusion", p.occlusion, "Probability a marker is hidden from one camera at a frame")
      ->capture_default_str();
  command->add_option("--occlusion-frames", p.occlusion_frames, "Mean length of an occlusion, frames")
      ->capture_default_str();
  command->add_option("--spurious", p.spurious, "False blobs per camera per frame (half static, half flicker)")
      ->capture_default_str();
  command->add_option("--drop-frames", p.drop_frames, "Probability a camera's whole frame is lost")
      ->capture_default_str();
  command->add_option("--marker-mm", p.marker_diameter_mm, "Marker diameter (sets blob size), mm")
      ->capture_default_str();
  command->add_option("--seed", w.seed, "Seed of the path and of every fault")->capture_default_str();
  command->add_flag("--json", args->json, "Print a JSON summary on stdout");
  command->callback([args] { RunSimWand(*args); });
}

void AddCalibrateWandCommand(CLI::App& app) {
  CLI::App& calibrate = CommandGroup(app, "calibrate", kCalibrateDescription);
  CLI::App* command = calibrate.add_subcommand("wand", "Camera poses from a wand session by bundle adjustment");
  auto args = std::make_shared<CalibrateWandArgs>();
  WandCalibrationOptions& o = args->options;
  command->add_option("session", args->session, "Session directory with the wand waving")->required();
  command->add_option("--intrinsics", args->intrinsics, "Calibration JSON giving each camera's intrinsics")
      ->required();
  command->add_option("--wand-length", args->wand_length_mm, "Distance between the wand's end markers, mm")
      ->required();
  command->add_option("-o,--output", args->output, "Calibration JSON to write")->required();
  command->add_option("--middle-marker", args->middle_marker_mm,
                      "Third marker this far from the first end, mm (0 = two-marker wand)")
      ->capture_default_str();
  command->add_option("--refine-intrinsics", args->refine, "none, focal-principal or all (with distortion)")
      ->capture_default_str();
  command->add_option("--reference-camera", args->reference_camera_id,
                      "Camera id defining the world frame (default: the one that saw the wand most)");
  command->add_option("--min-views", o.min_views_per_camera, "Wand views a camera needs to be accepted")
      ->capture_default_str();
  command->add_option("--min-coverage", o.min_coverage, "Fraction of a camera's image the wand must cover")
      ->capture_default_str();
  command->add_option("--max-rms", o.max_camera_rms_px, "Largest accepted reprojection RMS of a camera, px")
      ->capture_default_str();
  command->add_option("--threads", o.bundle.num_threads, "Solver threads")->capture_default_str();
  command->add_flag("--allow-partial", args->allow_partial, "Write the accepted cameras even if some are refused");
  command->add_flag("--json", args->json, "Print the report as one JSON object on stdout");
  command->callback([args] { RunCalibrateWand(*args); });
}

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

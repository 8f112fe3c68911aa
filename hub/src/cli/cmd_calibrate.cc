// Calibration commands: `sim wand` (a simulated wand session), `calibrate wand` (extrinsics by
// bundle adjustment), `calibrate world` (L-frame or floor), `calibrate intrinsics` (board
// images), `calibrate dlt` / `import-tsai` / `import-mcd` (seed 000's methods and files) and
// `eval-calibration` (accuracy against a truth rig). Each validates its inputs and throws a
// one-line reason; main() prints it and exits non-zero.
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

#include <Eigen/Geometry>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "calib/dlt.h"
#include "calib/intrinsics.h"
#include "calib/mcd.h"
#include "calib/session_frames.h"
#include "calib/tsai.h"
#include "calib/wand_calibration.h"
#include "calib/world_frame.h"
#include "cli/commands.h"
#include "util/json_file.h"
#include "util/log.h"
#include "cli/fault_options.h"
#include "cli/progress.h"
#include "eval/calibration_eval.h"
#include "ingest/session.h"
#include "recon/reconstructor.h"
#include "io/calibration_json.h"
#include "sim/project_session.h"
#include "sim/wand.h"

namespace mocap {
namespace {

constexpr const char* kSimDescription = "Simulator: virtual rigs, projected sessions with realistic faults";
constexpr const char* kCalibrateDescription =
    "Camera calibration: wand extrinsics, world frame, intrinsics, DLT and seed-format imports";


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
        throw UsageError(option + ": '" + item + "' is not a point 'x,y,z' (mm)");
      }
      points.emplace_back(x, y, z);
    }
    start = end + 1;
  }
  if (points.empty()) throw UsageError(option + ": no points given");
  return points;
}

// The session's frames; damage the reader skipped is reported on stderr, not hidden.
std::vector<FrameSet> LoadFramesReporting(const std::string& session) {
  std::vector<std::string> warnings;
  std::vector<FrameSet> frames = LoadSessionFrames(session, &warnings);
  for (const std::string& warning : warnings) log::Warn("{}", warning);
  return frames;
}

// ---- sim wand -------------------------------------------------------------------------------

struct SimWandArgs {
  std::string rig;
  std::string output;
  std::string lframe;
  bool json = false;
  WandMotionOptions wand;
  ProjectOptions project;
};

void RunSimWand(SimWandArgs args) {
  CheckOptions(args.project);
  if (args.wand.lframe_frames > 0) {
    args.wand.lframe_markers = args.lframe.empty() ? DefaultLFrame(args.wand.up_axis < 0 ? 2 : args.wand.up_axis)
                                                   : ParsePointList(args.lframe, "--lframe");
  }
  CheckOptions(args.wand);
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
  CheckOptions(wand);
  args.options.bundle.refine_intrinsics = IntrinsicsRefinementFromName(args.refine);
  const Rig intrinsics = LoadRigJson(args.intrinsics);
  if (args.reference_camera_id >= 0) {
    const Camera* reference = intrinsics.Find(static_cast<uint32_t>(args.reference_camera_id));
    if (reference == nullptr) {
      throw UsageError(fmt::format("--reference-camera {}: no such camera in {}", args.reference_camera_id,
                                              args.intrinsics));
    }
    args.options.initialization.reference_camera = static_cast<int>(reference - intrinsics.cameras.data());
  }
  CheckOptions(args.options);
  const std::vector<FrameSet> frames = LoadFramesReporting(args.session);
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

// ---- calibrate world ------------------------------------------------------------------------

struct CalibrateWorldArgs {
  std::string session;
  std::string calibration;
  std::string output;
  std::string lframe;
  int up_axis = 2;
  bool floor = false;
  bool json = false;
  LFrameOptions options;
};

// The input document with every camera's pose replaced, so that fields written by other steps
// (reports, residuals) survive.
nlohmann::json WithPoses(nlohmann::json document, const Rig& rig) {
  for (auto& camera : document["cameras"]) {
    const Camera* moved = rig.Find(camera["id"].get<uint32_t>());
    if (moved == nullptr) continue;
    nlohmann::json rotation = nlohmann::json::array();
    for (int r = 0; r < 3; ++r) rotation.push_back({moved->rotation(r, 0), moved->rotation(r, 1), moved->rotation(r, 2)});
    camera["rotation"] = rotation;
    camera["translation"] = {moved->translation.x(), moved->translation.y(), moved->translation.z()};
  }
  return document;
}

void RunCalibrateWorld(const CalibrateWorldArgs& args) {
  const int up_axis = args.up_axis;
  CheckOptions(args.options);
  const Rig rig = LoadRigJson(args.calibration);
  const std::vector<FrameSet> frames = LoadFramesReporting(args.session);
  WorldFrameFit fit;
  std::vector<Eigen::Vector3d> model;
  if (args.floor) {
    // Every marker reconstructed in the session lies on the floor.
    ReconstructorOptions recon_options;
    recon_options.use_predictions = false;
    Reconstructor reconstructor(rig, recon_options);
    std::vector<ReconstructedPoint> points;
    std::vector<Eigen::Vector3d> floor;
    for (const FrameSet& set : frames) {
      reconstructor.Process(set, {}, &points);
      for (const ReconstructedPoint& point : points) floor.push_back(point.point_in_world);
    }
    fit = LevelOnFloor(floor, rig, up_axis);
    fit.frames_used = static_cast<int>(frames.size());
  } else {
    model = args.lframe.empty() ? DefaultLFrame(up_axis) : ParsePointList(args.lframe, "--lframe");
    fit = LocateLFrame(frames, rig, model, args.options);
  }
  const Rig moved = TransformRig(rig, fit.new_from_old);
  nlohmann::json document = WithPoses(ReadJsonFile(args.calibration), moved);
  document["world_frame"] = {{"method", args.floor ? "floor" : "lframe"},
                             {"session", args.session},
                             {"frames_used", fit.frames_used},
                             {"fit_rms_mm", fit.fit_rms_mm},
                             {"up", UpAxisName(args.up_axis)}};
  WriteJsonFile(document, args.output);
  if (args.json) {
    std::printf("%s\n", document["world_frame"].dump().c_str());
  } else {
    std::printf("calibrate world: %s from %d frames, fit RMS %.3f mm; world origin moved by %.1f mm, turned by "
                "%.2f deg; wrote %s\n",
                args.floor ? "floor plane" : "L-frame", fit.frames_used, fit.fit_rms_mm,
                fit.new_from_old.translation.norm(),
                Eigen::AngleAxisd(fit.new_from_old.rotation).angle() * 180.0 / M_PI, args.output.c_str());
  }
}

// ---- calibrate intrinsics -------------------------------------------------------------------

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
  writer.Create(args.output, info);
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
  AddUpAxisOption(*command, &args->wand.up_axis, true, "Vertical axis: x, y, z or auto (from the cameras)");
  command->add_option("--lframe-frames", w.lframe_frames, "Static L-frame frames after the waving")
      ->capture_default_str();
  command->add_option("--lframe", args->lframe,
                      "L-frame markers in world mm, 'x,y,z;x,y,z;...' (default: 4-marker L on the floor)");
  AddCameraFaultOptions(command, &p);
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

void AddCalibrateWorldCommand(CLI::App& app) {
  CLI::App& calibrate = CommandGroup(app, "calibrate", kCalibrateDescription);
  CLI::App* command =
      calibrate.add_subcommand("world", "Put the world frame on an L-frame (or level it on floor markers)");
  auto args = std::make_shared<CalibrateWorldArgs>();
  command->add_option("session", args->session, "Session in which the L-frame (or floor markers) lies still")
      ->required();
  command->add_option("--calibration", args->calibration, "Calibration JSON to move into the new world frame")
      ->required();
  command->add_option("-o,--output", args->output, "Calibration JSON to write")->required();
  command->add_option("--lframe", args->lframe,
                      "L-frame markers in the new world, mm, 'x,y,z;x,y,z;...' (default: 4-marker L on the floor)");
  AddUpAxisOption(*command, &args->up_axis, false, "Vertical axis of the new world: x, y or z");
  command->add_flag("--floor", args->floor,
                    "Level on floor markers instead (origin at their centroid, heading kept)");
  command->add_option("--max-fit-rms", args->options.max_fit_rms_mm, "L-frame match tolerance, mm")
      ->capture_default_str();
  command->add_option("--min-frames", args->options.min_frames, "Frames in which the L-frame must be found")
      ->capture_default_str();
  command->add_flag("--json", args->json, "Print a JSON summary on stdout");
  command->callback([args] { RunCalibrateWorld(*args); });
}

void AddCalibrateIntrinsicsCommand(CLI::App& app) {
  CLI::App& calibrate = CommandGroup(app, "calibrate", kCalibrateDescription);
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
  CLI::App& calibrate = CommandGroup(app, "calibrate", kCalibrateDescription);
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

void AddCalibrateImportTsaiCommand(CLI::App& app) {
  CLI::App& calibrate = CommandGroup(app, "calibrate", kCalibrateDescription);
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
  CLI::App& calibrate = CommandGroup(app, "calibrate", kCalibrateDescription);
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

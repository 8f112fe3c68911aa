// `calibrate wand` (camera poses by bundle adjustment of a wand session, with a per-camera
// report) and `calibrate world` (the world frame from an L-frame or floor markers).
#include <cmath>
#include <cstdio>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "calib/intrinsics.h"
#include "calib/wand_calibration.h"
#include "calib/world_frame.h"
#include "cli/calibrate_helpers.h"
#include "cli/commands.h"
#include "ingest/session.h"
#include "io/calibration_json.h"
#include "recon/reconstructor.h"
#include "simcore/wand.h"
#include "util/json_file.h"

namespace mocap {
namespace {

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
          {"reprojection_rms_definition", "2-D error length per observation"},
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
  std::printf("reprojection RMS %.3f px (2-D error length per observation); wand length error over %zu frames: mean %+.3f mm, "
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

}  // namespace

void AddCalibrateWandCommand(CLI::App& app) {
  CLI::App& calibrate = CommandGroup(app, "calibrate");
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
  CLI::App& calibrate = CommandGroup(app, "calibrate");
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

}  // namespace mocap

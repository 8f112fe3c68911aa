// `calibrate wand` (camera poses by bundle adjustment of a wand session, with a rated per-camera
// report and, with --report, an HTML page of plots; with --live the session is recorded and
// solved by a running serve, see wand_client.h) and `calibrate world` (the world frame from an
// L-frame or floor markers).
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "calib/intrinsics.h"
#include "calib/wand_calibration.h"
#include "calib/wand_report.h"
#include "calib/world_frame.h"
#include "cli/api_client.h"
#include "cli/calibrate_helpers.h"
#include "cli/commands.h"
#include "cli/wand_client.h"
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
  std::string report_dir;
  // --live
  bool live = false;
  std::string api;
  size_t min_samples = 300;
  double coverage_target = 0.4;
  double timeout_s = 300.0;
  bool apply = false;
  bool save = false;
};

// --live: serve records the session and solves it; the same options travel in the start request.
void RunLiveCalibrateWand(const CalibrateWandArgs& args) {
  if (args.reference_camera_id >= 0) throw UsageError("--reference-camera is for the offline solve");
  if (args.save && !args.apply) throw UsageError("--save needs --apply");
  LiveWandingArgs live;
  live.api = args.api;
  live.session = args.session;
  live.output = args.output;
  live.report_dir = args.report_dir;
  live.apply = args.apply;
  live.save = args.save;
  live.allow_partial = args.allow_partial;
  live.json = args.json;
  live.start = {{"wand_length_mm", args.wand_length_mm},
                {"middle_marker_mm", args.middle_marker_mm},
                {"min_samples", args.min_samples},
                {"coverage_target", args.coverage_target},
                {"timeout_s", args.timeout_s},
                {"refine_intrinsics", args.refine}};
  if (!args.intrinsics.empty()) live.start["intrinsics"] = ReadJsonFile(args.intrinsics);
  RunLiveWanding(live);
}

void RunCalibrateWand(CalibrateWandArgs args) {
  const WandGeometry wand = args.middle_marker_mm > 0.0
                                ? WandGeometry::ThreeMarker(args.wand_length_mm, args.middle_marker_mm)
                                : WandGeometry::TwoMarker(args.wand_length_mm);
  CheckOptions(wand);
  if (args.live) {
    RunLiveCalibrateWand(args);
    return;
  }
  if (args.intrinsics.empty()) throw UsageError("--intrinsics is required (but for --live)");
  if (args.output.empty()) throw UsageError("-o/--output is required (but for --live)");
  if (args.apply || args.save) throw UsageError("--apply and --save go with --live");
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
  const RatingThresholds thresholds;
  const nlohmann::json report = WandResultJson(result, wand, thresholds);
  if (args.json) {
    std::printf("%s\n", report.dump().c_str());
  } else {
    PrintWandReport(report);
  }
  // The report is written whatever the outcome: a refused camera is what it helps to explain.
  if (!args.report_dir.empty()) {
    const std::string title = std::filesystem::path(args.session).filename().string();
    const std::filesystem::path dir(args.report_dir);
    WriteWandReport(WandReportFigures(result, wand, thresholds, title), (dir / "wand_report.html").string(),
                    (dir / "wand_figures.json").string());
    if (!args.json) std::printf("report: %s\n", (dir / "wand_report.html").string().c_str());
  }
  if (!result.AllAccepted() && !args.allow_partial) {
    std::string reasons;
    for (const auto& c : result.cameras) {
      if (!c.accepted) reasons += fmt::format("{}camera {}: {}", reasons.empty() ? "" : "; ", c.id, c.reason);
    }
    throw std::runtime_error("calibration refused, nothing written (--allow-partial writes the accepted cameras): " +
                             reasons);
  }
  WriteJsonFile(WandCalibrationDocument(result, report), args.output);
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
  command->add_option("session", args->session,
                      "Session directory with the wand waving (with --live: the name serve records it under)")
      ->required();
  command->add_option("--intrinsics", args->intrinsics,
                      "Calibration JSON giving each camera's intrinsics (with --live: default serve's calibration)");
  command->add_option("--wand-length", args->wand_length_mm, "Distance between the wand's end markers, mm")
      ->required();
  command->add_option("-o,--output", args->output, "Calibration JSON to write (optional with --live)");
  command->add_option("--report", args->report_dir,
                      "Directory for wand_report.html (plots) and wand_figures.json (their figures)");
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
  command->add_flag("--live", args->live,
                    "Wand through a running serve: per-camera samples, coverage and advice while waving, then its "
                    "solve and rating");
  AddApiOption(*command, &args->api);
  command->add_option("--min-samples", args->min_samples, "--live: wand samples every camera needs")
      ->check(CLI::Range(10, 1000000))
      ->capture_default_str();
  command->add_option("--coverage-target", args->coverage_target,
                      "--live: share of every camera's image the wand must cover before serve stops")
      ->check(CLI::Range(0.05, 1.0))
      ->capture_default_str();
  command->add_option("--timeout", args->timeout_s, "--live: stop collecting after this many seconds, s")
      ->check(CLI::Range(1.0, 3600.0))
      ->capture_default_str();
  command->add_flag("--apply", args->apply, "--live: switch serve's live reconstruction to the new calibration");
  command->add_flag("--save", args->save, "--live with --apply: also write it over serve's --calibration file");
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
                      "L-frame markers in the new world, mm, 'x,y,z;x,y,z;...' (default: a 4-marker L on the floor: "
                      "the origin, 200 and 500 mm along one arm, 350 mm along the other; arms along x and y with "
                      "z up, z and x with y up)");
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

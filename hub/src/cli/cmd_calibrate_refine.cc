// `calibrate refine SESSION --calibration CAL -o NEW`: continuous calibration offline. The
// session (an ordinary capture) is reconstructed with CAL frame by frame; the markers and their
// views give each camera's leave-one-out residuals; cameras whose residuals say they moved are
// re-solved with the others held (calib/extrinsic_refinement.h). NEW is CAL with the accepted
// poses and a "refinement" report; nothing is written when a moved camera cannot be solved.
#include <cmath>
#include <cstdio>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "calib/extrinsic_refinement.h"
#include "calib/marker_residuals.h"
#include "cli/commands.h"
#include "ingest/session.h"
#include "io/calibration_json.h"
#include "util/json_file.h"
#include "util/log.h"

namespace mocap {
namespace {

struct CalibrateRefineArgs {
  std::string session;
  std::string calibration;
  std::string output;
  size_t every = 1;
  bool json = false;
  MarkerResidualOptions residuals;
  ExtrinsicRefinementOptions refinement;
};

nlohmann::json ResidualsJson(const CameraResiduals& r) {
  return {{"observations", r.observations},
          {"median_px", r.median_px},
          {"rms_px", r.rms_px},
          {"mean_px", {r.mean_px.x(), r.mean_px.y()}}};
}

nlohmann::json RefinementJson(const ExtrinsicRefinement& refined, const std::string& session, uint64_t frames) {
  nlohmann::json cameras = nlohmann::json::array();
  for (const CameraRefinement& c : refined.cameras) {
    nlohmann::json camera = {{"id", c.camera_id},
                             {"state_before", CameraPoseStateName(c.state_before)},
                             {"state_after", CameraPoseStateName(c.state_after)},
                             {"before", ResidualsJson(c.before)},
                             {"after", ResidualsJson(c.after)},
                             {"refined", c.refined},
                             {"accepted", c.accepted}};
    if (c.refined) {
      camera["centre_change_mm"] = c.centre_change_mm;
      camera["rotation_change_deg"] = c.rotation_change_deg;
      camera["inlier_views"] = c.inlier_views;
      camera["outlier_views"] = c.outlier_views;
      const CameraRelocalization& r = c.relocalization;
      camera["relocalization"] = {{"ok", r.ok},
                                  {"points", r.points},
                                  {"shift_px", {r.shift_px.x(), r.shift_px.y()}},
                                  {"candidates", r.candidates},
                                  {"ransac_inliers", r.ransac_inliers},
                                  {"inliers", r.inliers},
                                  {"gate_px", r.gate_px},
                                  {"median_px", r.median_px}};
      if (!c.note.empty()) camera["note"] = c.note;
    }
    cameras.push_back(camera);
  }
  return {{"session", session},
          {"frames", frames},
          {"samples", refined.samples},
          {"points_solved", refined.points_solved},
          {"baseline_px", refined.baseline_px},
          {"changed", refined.Changed()},
          {"cameras", cameras}};
}

// The input document with the accepted cameras' poses replaced: every other field, and every
// other camera's pose, stays exactly as it was written.
nlohmann::json WithRefinedPoses(nlohmann::json document, const ExtrinsicRefinement& refined) {
  for (const CameraRefinement& c : refined.cameras) {
    const Camera* moved = refined.rig.Find(c.camera_id);
    if (c.accepted && moved != nullptr) document = WithCameraPose(std::move(document), *moved);
  }
  return document;
}

void RunCalibrateRefine(const CalibrateRefineArgs& args) {
  CheckOptions(args.residuals);
  CheckOptions(args.refinement);
  const Rig rig = LoadRigJson(args.calibration);
  nlohmann::json document = ReadJsonFile(args.calibration);
  SessionReader reader;
  reader.Open(args.session);
  MarkerResidualCollector collector(rig, args.residuals);
  FrameSet set;
  uint64_t frames = 0;
  while (reader.Next(&set)) {
    if (frames++ % args.every == 0) collector.Add(set);
  }
  for (const std::string& warning : reader.warnings()) log::Warn("{}", warning);
  if (frames == 0) throw std::runtime_error(args.session + ": no frames");
  if (collector.samples().empty())
    throw std::runtime_error(args.session + ": no marker was reconstructed with " + args.calibration +
                             " (a capture of markers seen by 3+ cameras is needed)");
  const ExtrinsicRefinement refined = RefineExtrinsics(rig, collector.samples(), collector.blobs(), args.refinement);
  const nlohmann::json report = RefinementJson(refined, args.session, frames);
  std::vector<std::string> refused;
  for (const CameraRefinement& c : refined.cameras) {
    if (c.refined && !c.accepted) refused.push_back("camera " + std::to_string(c.camera_id) + ": " + c.note);
  }
  if (args.json) {
    std::printf("%s\n", report.dump().c_str());
  } else {
    for (const CameraRefinement& c : refined.cameras) {
      std::printf("camera %u: %-8s median %.3f px (%zu views)", c.camera_id, CameraPoseStateName(c.state_before),
                  c.before.median_px, c.before.observations);
      if (c.refined) {
        std::printf(" -> %s %.3f px, moved %.2f mm %.3f deg%s", CameraPoseStateName(c.state_after), c.after.median_px,
                    c.centre_change_mm, c.rotation_change_deg, c.accepted ? "" : " (refused)");
      }
      std::printf("\n");
    }
  }
  if (!refused.empty()) {
    std::string reasons;
    for (const std::string& r : refused) reasons += (reasons.empty() ? "" : "; ") + r;
    throw std::runtime_error("not written: " + reasons);
  }
  document = WithRefinedPoses(document, refined);
  document["refinement"] = report;
  WriteJsonFile(document, args.output);
  if (!args.json) {
    std::printf("calibrate refine: %s from %llu frames (%zu marker samples, baseline %.3f px); wrote %s\n",
                refined.Changed() ? "cameras re-solved" : "no camera moved, calibration unchanged",
                static_cast<unsigned long long>(frames), refined.samples, refined.baseline_px, args.output.c_str());
  }
}

}  // namespace

void AddCalibrateRefineCommand(CLI::App& app) {
  CLI::App& calibrate = CommandGroup(app, "calibrate");
  CLI::App* command = calibrate.add_subcommand(
      "refine", "Re-solve cameras that moved since calibration from an ordinary capture's markers");
  auto args = std::make_shared<CalibrateRefineArgs>();
  BumpDetectionOptions& d = args->refinement.detection;
  command->add_option("session", args->session, "Session directory of an ordinary capture")->required();
  command->add_option("--calibration", args->calibration, "Calibration JSON the session was captured with")
      ->required();
  command->add_option("-o,--output", args->output, "Calibration JSON to write")->required();
  command->add_option("--every", args->every, "Use every Nth frame set")
      ->check(CLI::Range(size_t{1}, size_t{1000000}))
      ->capture_default_str();
  command->add_option("--drift-px", d.drift_px, "A camera whose median residual is above this is drifting, px")
      ->check(FiniteRange(1e-3, 1e3))
      ->capture_default_str();
  command->add_option("--bump-px", d.bump_px, "A camera whose median residual is above this is bumped, px")
      ->check(FiniteRange(1e-3, 1e3))
      ->capture_default_str();
  command->add_option("--baseline-px", d.baseline_px,
                      "The rig's residual when calibrated, px (0: the median over the cameras)")
      ->check(FiniteRange(0.0, 1e3))
      ->capture_default_str();
  command->add_option("--threads", args->refinement.num_threads, "Solver threads")
      ->check(CLI::Range(1, 64))
      ->capture_default_str();
  command->add_flag("--json", args->json, "Print the report as one JSON object on stdout");
  command->callback([args] { RunCalibrateRefine(*args); });
}

}  // namespace mocap

// `sim wand`: a calibration wand (and optionally an L-frame) waved through a rig's volume,
// projected with the simulator's camera faults into a session (and, with --motion, written as
// TRC so that `sim render` makes camera frames of it for nodes to replay).
#include <cstdio>
#include <memory>
#include <string>

#include <nlohmann/json.hpp>

#include "calib/wand_calibration.h"
#include "calib/world_frame.h"
#include "cli/calibrate_helpers.h"
#include "cli/commands.h"
#include "cli/fault_options.h"
#include "cli/progress.h"
#include "ingest/session.h"
#include "io/calibration_json.h"
#include "io/trc.h"
#include "sim/project_session.h"
#include "simcore/wand.h"

namespace mocap {
namespace {

struct SimWandArgs {
  std::string rig;
  std::string output;
  std::string lframe;
  std::string motion;  // also write the wand's motion as TRC (for `sim render`)
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
  if (!args.motion.empty()) WriteTrc(motion, args.motion);
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

}  // namespace

void AddSimWandCommand(CLI::App& app) {
  CLI::App& sim = CommandGroup(app, "sim");
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
  command->add_option("--single-marker-frames", w.single_marker_frames,
                      "The first N frames show only the wand's first marker (a single marker waved; the frames "
                      "after them show the whole wand, the scale bar of `calibrate marker`)")
      ->capture_default_str();
  command->add_option("--lframe-frames", w.lframe_frames, "Static L-frame frames after the waving")
      ->capture_default_str();
  command->add_option("--lframe", args->lframe,
                      "L-frame markers in world mm, 'x,y,z;x,y,z;...' (default: 4-marker L on the floor)");
  AddCameraFaultOptions(command, &p);
  command->add_option("--seed", w.seed, "Seed of the path and of every fault")->capture_default_str();
  command->add_option("--motion", args->motion,
                      "Also write the wand's motion as TRC, to render camera frames from (sim render)");
  command->add_flag("--json", args->json, "Print a JSON summary on stdout");
  command->callback([args] { RunSimWand(*args); });
}

}  // namespace mocap

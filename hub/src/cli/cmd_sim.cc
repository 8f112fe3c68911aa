// `sim rig` and `sim project`: virtual rigs around a motion and simulated sessions with faults.
#include <cstdio>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <string>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "cli/commands.h"
#include "cli/fault_options.h"
#include "cli/progress.h"
#include "io/calibration_json.h"
#include "io/trc.h"
#include "bodies/body_definition.h"
#include "sim/body_scene.h"
#include "sim/project_session.h"
#include "simcore/camera_bump.h"
#include "simcore/ring_rig.h"

namespace mocap {
namespace {

struct SimRigArgs {
  std::string motion;
  std::string output;
  int up_axis = -1;
  bool no_distortion = false;
  bool json = false;
  RingRigOptions rig;
};

void RunSimRig(const SimRigArgs& args) {
  RingRigOptions options = args.rig;
  options.lens_distortion = !args.no_distortion;
  CheckOptions(options);
  const MarkerTrajectories motion = ReadTrc(args.motion);
  const MotionVolume volume = ComputeMotionVolume(motion, args.up_axis);
  const Rig rig = MakeRingRig(volume, options);
  SaveRigJson(rig, args.output);
  const char axes[] = "xyz";
  if (args.json) {
    std::printf("%s\n", nlohmann::json({{"rig", args.output},
                                        {"cameras", rig.cameras.size()},
                                        {"up", std::string(1, axes[volume.up_axis])},
                                        {"volume_min", {volume.min.x(), volume.min.y(), volume.min.z()}},
                                        {"volume_max", {volume.max.x(), volume.max.y(), volume.max.z()}}})
                            .dump()
                            .c_str());
  } else {
    const Eigen::Vector3d size = volume.max - volume.min;
    std::printf("%s: %zu cameras around a %.0f x %.0f x %.0f mm volume, up = %c%s\n", args.output.c_str(),
                rig.cameras.size(), size.x(), size.y(), size.z(), axes[volume.up_axis],
                args.up_axis < 0 ? " (detected)" : "");
  }
}

struct SimProjectArgs {
  std::string motion;
  std::string rig;
  std::string output;
  bool json = false;
  ProjectOptions project;
  std::string bodies;  // rigid bodies to add (bodies file); empty: none
  BodySceneOptions body_paths;
  std::vector<std::string> bumps;  // CAM:DEG:MM
  double bump_from_s = 0.0;
  uint64_t bump_seed = 1;
  FreeRunOptions free_run;
};

std::vector<CameraBump> ParseBumps(const SimProjectArgs& args, const Rig& rig) {
  std::vector<CameraBump> bumps;
  for (const std::string& text : args.bumps) {
    CameraBump bump;
    try {
      bump = ParseCameraBump(text);
    } catch (const std::invalid_argument& error) {
      throw UsageError(std::string("--bump: ") + error.what());
    }
    if (rig.Find(bump.camera_id) == nullptr)
      throw UsageError("--bump: " + args.rig + " has no camera " + std::to_string(bump.camera_id));
    bump.from_s = args.bump_from_s;
    bump.seed = args.bump_seed + bumps.size();
    bumps.push_back(bump);
  }
  return bumps;
}

void RunSimProject(const SimProjectArgs& args) {
  CheckOptions(args.project);
  CheckOptions(args.body_paths);
  CheckOptions(args.free_run);
  FreeRunOptions free_run = args.free_run;
  free_run.seed = args.project.seed;
  MarkerTrajectories motion = ReadTrc(args.motion);
  const Rig rig = LoadRigJson(args.rig);
  const std::vector<CameraBump> bumps = ParseBumps(args, rig);
  if (motion.NumFrames() == 0) throw std::runtime_error(args.motion + ": no frames");
  // Rigid bodies fly around the subject: their markers join the truth, their poses go beside it.
  std::vector<RigidBodyDefinition> bodies;
  std::vector<BodyPoseRow> body_poses;
  if (!args.bodies.empty()) {
    bodies = ReadBodiesFile(args.bodies);
    try {
      BodyScene scene = AddRigidBodies(motion, bodies, args.body_paths);
      motion = std::move(scene.scene);
      body_poses = std::move(scene.poses);
    } catch (const std::invalid_argument& error) {
      throw std::runtime_error(args.motion + ": " + error.what());
    }
  }
  ProgressBar progress("sim project", motion.NumFrames());
  const ProjectSessionStats stats = ProjectSession(motion, rig, args.project, args.output,
                                                   [&](size_t done, size_t) { progress.Update(done); }, bumps,
                                                   free_run);
  progress.Finish();
  if (!bodies.empty())
    WriteBodyPoses((std::filesystem::path(args.output) / "truth.bodies.tsv").string(), bodies, body_poses, motion.rate_hz);
  const double reconstructible = stats.present > 0 ? static_cast<double>(stats.reconstructible) / stats.present : 0.0;
  if (args.json) {
    std::printf("%s\n", nlohmann::json({{"session", args.output},
                                        {"frames", stats.frames},
                                        {"camera_frames", stats.camera_frames},
                                        {"dropped_camera_frames", stats.dropped_camera_frames},
                                        {"late_camera_frames", stats.late_camera_frames},
                                        {"blobs", stats.blobs},
                                        {"merged_blobs", stats.merged_blobs},
                                        {"reconstructible_fraction", reconstructible}})
                            .dump()
                            .c_str());
  } else {
    std::printf("%s: %llu frames, %llu camera frames (%llu dropped), %llu blobs (%llu merged), "
                "%.2f%% of marker positions seen by >= 2 cameras\n",
                args.output.c_str(), static_cast<unsigned long long>(stats.frames),
                static_cast<unsigned long long>(stats.camera_frames),
                static_cast<unsigned long long>(stats.dropped_camera_frames),
                static_cast<unsigned long long>(stats.blobs), static_cast<unsigned long long>(stats.merged_blobs),
                100.0 * reconstructible);
  }
}

}  // namespace

void AddSimRigCommand(CLI::App& app) {
  CLI::App& sim = CommandGroup(app, "sim");
  CLI::App* command = sim.add_subcommand("rig", "Place a ring of cameras around a motion's volume");
  auto args = std::make_shared<SimRigArgs>();
  command->add_option("--motion", args->motion, "Motion (TRC) whose volume the cameras must see")->required();
  command->add_option("--cameras", args->rig.cameras, "Number of cameras")->required();
  command->add_option("-o,--output", args->output, "Rig file to write (calibration JSON)")->required();
  command->add_option("--width", args->rig.width, "Image width, px")->capture_default_str();
  command->add_option("--height", args->rig.height, "Image height, px")->capture_default_str();
  command->add_option("--fov-deg", args->rig.fov_deg, "Horizontal field of view, degrees")->capture_default_str();
  AddUpAxisOption(*command, &args->up_axis, true, "Vertical axis of the motion: x, y, z or auto (detected)");
  command->add_option("--seed", args->rig.seed, "Seed of placement and lens differences")->capture_default_str();
  command->add_option("--mount-above-mm", args->rig.mount_above_mm, "Camera height above the volume's top, mm")
      ->capture_default_str();
  command->add_option("--margin", args->rig.margin, "Distance factor beyond a tight fit (>= 1)")
      ->capture_default_str();
  command->add_flag("--no-distortion", args->no_distortion, "Ideal pinhole lenses");
  command->add_flag("--json", args->json, "Print a JSON summary on stdout");
  command->callback([args] { RunSimRig(*args); });
}

void AddSimProjectCommand(CLI::App& app) {
  CLI::App& sim = CommandGroup(app, "sim");
  CLI::App* command = sim.add_subcommand("project", "Project a motion through a rig into a session with faults");
  auto args = std::make_shared<SimProjectArgs>();
  ProjectOptions& p = args->project;
  command->add_option("--motion", args->motion, "Motion (TRC): the ground truth")->required();
  command->add_option("--rig", args->rig, "Rig / calibration JSON")->required();
  command->add_option("-o,--output", args->output, "Session directory to write")->required();
  AddCameraFaultOptions(command, &p);
  command->add_option("--merge-px", p.merge_px,
                      "Blobs closer than this merge; negative (default) = when they touch, from blob size")
      ->capture_default_str();
  command->add_option("--late", p.late, "Probability a camera frame's datagrams arrive late")
      ->capture_default_str();
  command->add_option("--late-frames", p.late_frames, "How many frames a late camera frame lags")
      ->capture_default_str();
  command->add_option("--seed", p.seed, "Seed of every fault")->capture_default_str();
  command->add_option("--bodies", args->bodies,
                      "Rigid bodies file: each body flies around the subject (markers <body>:1...; true poses "
                      "in SESSION/truth.bodies.tsv)")
      ->check(CLI::ExistingFile);
  command->add_option("--body-speed", args->body_paths.speed_rad_s, "Bodies' speed around the subject, rad/s")
      ->capture_default_str();
  command->add_option("--body-spin", args->body_paths.spin_deg_s, "Bodies' spin, degrees/s")->capture_default_str();
  command->add_option("--body-seed", args->body_paths.seed, "Seed of the bodies' paths")->capture_default_str();
  command->add_option("--bump", args->bumps,
                      "Bump a camera after calibration: CAM:DEG:MM rotates camera CAM by DEG degrees and moves it "
                      "by MM mm (random axis and direction; repeatable); calibration.json stays the rig given, the "
                      "bumped rig is SESSION/truth.calibration.json");
  command->add_option("--bump-from-s", args->bump_from_s, "When the bumps happen, s after the first frame")
      ->check(FiniteRange(0.0, 1e7))
      ->capture_default_str();
  command->add_option("--bump-seed", args->bump_seed, "Seed of the bumps' axes and directions")->capture_default_str();
  command->add_flag("--free-run", args->free_run.enabled,
                    "Free-running cameras (no trigger wire): each exposes at a random phase, its rate off by "
                    "--rate-error-ppm, its time stamps with --time-jitter-ms (session.json: free_run)");
  command->add_option("--rate-error-ppm", args->free_run.rate_error_ppm,
                      "Free run: each camera's rate error, drawn within +- this, ppm")
      ->capture_default_str();
  command->add_option("--time-jitter-ms", args->free_run.jitter_ms,
                      "Free run: sigma of the capture time stamps' error, ms (USB webcams: about 1)")
      ->capture_default_str();
  command->add_flag("--json", args->json, "Print a JSON summary on stdout");
  command->callback([args] { RunSimProject(*args); });
}

}  // namespace mocap

// `sim render`: camera frames of a motion seen through a rig, one replayable recording per
// camera (FRAMES_DIR/cam<ID>/frames.mcf) beside truth.trc, calibration.json and visibility.tsv.
#include <cstdio>
#include <memory>
#include <stdexcept>
#include <string>

#include <nlohmann/json.hpp>

#include "cli/commands.h"
#include "cli/progress.h"
#include "io/calibration_json.h"
#include "io/trc.h"
#include "sim/frame_render.h"

namespace mocap {
namespace {

struct SimRenderArgs {
  std::string motion;
  std::string rig;
  std::string output;
  bool json = false;
  FrameRenderOptions options;
};

void RunSimRender(const SimRenderArgs& args) {
  CheckOptions(args.options);
  const MarkerTrajectories motion = ReadTrc(args.motion);
  const Rig rig = LoadRigJson(args.rig);
  if (motion.NumFrames() == 0) throw std::runtime_error(args.motion + ": no frames");
  ProgressBar progress("sim render", motion.NumFrames());
  const FrameRenderStats stats = RenderFrames(motion, rig, args.options, args.output,
                                              [&](size_t done, size_t) { progress.Update(done); });
  progress.Finish();
  const double reconstructible = stats.present > 0 ? static_cast<double>(stats.reconstructible) / stats.present : 0.0;
  const double per_frame = stats.camera_frames > 0 ? static_cast<double>(stats.bytes) / stats.camera_frames : 0.0;
  if (args.json) {
    std::printf("%s\n", nlohmann::json({{"frames_dir", args.output},
                                        {"cameras", rig.cameras.size()},
                                        {"frames", stats.frames},
                                        {"camera_frames", stats.camera_frames},
                                        {"spots", stats.spots},
                                        {"bytes", stats.bytes},
                                        {"reconstructible_fraction", reconstructible}})
                            .dump()
                            .c_str());
  } else {
    std::printf("%s: %zu cameras x %llu frames, %llu spots, %.1f MB on disk (%.1f kB per camera frame), "
                "%.2f%% of marker positions seen by >= 2 cameras\n",
                args.output.c_str(), rig.cameras.size(), static_cast<unsigned long long>(stats.frames),
                static_cast<unsigned long long>(stats.spots), static_cast<double>(stats.bytes) / 1e6,
                per_frame / 1e3, 100.0 * reconstructible);
  }
}

}  // namespace

void AddSimRenderCommand(CLI::App& app) {
  CLI::App& sim = CommandGroup(app, "sim");
  CLI::App* command = sim.add_subcommand("render", "Render a motion through a rig into replayable camera frames");
  auto args = std::make_shared<SimRenderArgs>();
  FrameRenderOptions& o = args->options;
  command->add_option("--motion", args->motion, "Motion (TRC): the ground truth")->required();
  command->add_option("--rig", args->rig, "Rig / calibration JSON")->required();
  command->add_option("-o,--output", args->output, "Frames directory to write (cam<ID>/ per camera)")->required();
  command->add_option("--marker-mm", o.project.marker_diameter_mm, "Marker diameter (spot size follows distance), mm")
      ->capture_default_str();
  command->add_option("--occlusion", o.project.occlusion, "Probability a marker is hidden from one camera at a frame")
      ->capture_default_str();
  command->add_option("--occlusion-frames", o.project.occlusion_frames, "Mean length of an occlusion, frames")
      ->capture_default_str();
  command->add_option("--background", o.render.background, "Background grey level")->capture_default_str();
  command->add_option("--noise", o.render.noise_sigma, "Sensor noise sigma, grey levels")->capture_default_str();
  command->add_option("--shot-noise", o.render.shot_noise, "Photon noise on spots: sigma = k * sqrt(signal)")
      ->capture_default_str();
  command->add_option("--flicker", o.render.flicker, "Marker brightness varies by up to this fraction per frame")
      ->capture_default_str();
  command->add_option("--blur-px", o.blur_px, "Lens/sensor blur (PSF sigma), px")->capture_default_str();
  command->add_option("--gain", o.gain, "Marker brightness factor (exposure x gain)")->capture_default_str();
  command->add_option("--reflections", o.reflections, "Static reflections (fixed false spots) per camera")
      ->capture_default_str();
  command->add_option("--flicker-spots", o.flicker_spots, "Flickering false spots per camera per frame")
      ->capture_default_str();
  command->add_option("--zlib-level", o.zlib_level, "Compression of stored tiles, 0..9")->capture_default_str();
  command->add_option("--seed", o.project.seed, "Seed of occlusion, reflections and flicker")->capture_default_str();
  command->add_flag("--json", args->json, "Print a JSON summary on stdout");
  command->callback([args] {
    SimRenderArgs run = *args;
    // Sensor noise and flicker follow the one seed so a run replays exactly.
    run.options.render.noise_seed = run.options.project.seed;
    run.options.render.seed = run.options.project.seed;
    RunSimRender(run);
  });
}

}  // namespace mocap

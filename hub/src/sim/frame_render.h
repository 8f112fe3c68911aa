// `sim render` as a library call: renders a motion through a rig into recorded camera frames,
// one FRAMES_DIR/cam<ID>/frames.mcf per camera (replayable by `mocap-node --source replay:`),
// beside FRAMES_DIR/truth.trc, calibration.json and visibility.tsv for evaluation.
#pragma once

#include <cstdint>
#include <functional>
#include <string>

#include "geometry/camera.h"
#include "io/marker_trajectories.h"
#include "simcore/projector.h"
#include "sim/spot_render.h"

namespace mocap {

struct FrameRenderOptions {
  // Marker visibility: occlusion, marker diameter (spot size follows distance) and the seed come
  // from here; the centroid-level faults (noise_px, merge_px, spurious, drop_frames) do not
  // apply, because the rendered image produces those effects itself (sensor noise, touching
  // spots) or they are set below.
  ProjectOptions project;
  // Background, sensor noise, shot noise and marker flicker of the images.
  SpotRenderOptions render;
  // Static reflections per camera (fixed bright spots, e.g. shiny fittings in view).
  int reflections = 0;
  // Flickering false spots per camera per frame (Poisson mean; each lasts one frame).
  double flicker_spots = 0.0;
  // Sigma of the lens and sensor point-spread function, px: a marker's image is its disc
  // blurred by it, so even a far marker lights a few pixels, as on a real camera.
  double blur_px = 0.7;
  // Multiplies the marker brightness of the projector's model (exposure x gain). Above 1, near
  // markers saturate, as a real exposure is set so the faintest far marker clears the threshold.
  double gain = 2.5;
  int zlib_level = 1;

  // Throws std::invalid_argument naming the bad option.
  void Check() const;
};

struct FrameRenderStats {
  uint64_t frames = 0;
  uint64_t camera_frames = 0;
  uint64_t spots = 0;
  uint64_t bytes = 0;  // on disk, all cameras' frames files
  // Marker-frames seen by at least two cameras, out of present marker-frames.
  uint64_t reconstructible = 0;
  uint64_t present = 0;
};

// Directory of camera `id`'s frames under dir: dir/cam<ID>.
std::string CameraFramesDir(const std::string& dir, uint32_t id);

// progress(done, total) is called after each frame when given. Throws std::runtime_error on
// file errors and std::invalid_argument on bad options or inputs.
FrameRenderStats RenderFrames(const MarkerTrajectories& motion, const Rig& rig, const FrameRenderOptions& options,
                              const std::string& dir,
                              const std::function<void(size_t, size_t)>& progress = nullptr);

}  // namespace mocap

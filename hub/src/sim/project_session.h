// `sim project` as a library call: projects a motion through a rig with faults and writes a
// session directory exactly as `record` would (raw log + session.json through SessionWriter),
// plus truth.trc, calibration.json and visibility.tsv for evaluation. With camera bumps the
// session is seen by a rig that changes mid-session while calibration.json stays the rig given
// (what the hub was calibrated with); the rig after the bumps is truth.calibration.json.
#pragma once

#include <cstdint>
#include <functional>
#include <string>

#include "geometry/camera.h"
#include "io/marker_trajectories.h"
#include "simcore/camera_bump.h"
#include "simcore/projector.h"

namespace mocap {

struct ProjectSessionStats {
  uint64_t frames = 0;
  uint64_t camera_frames = 0;
  uint64_t dropped_camera_frames = 0;
  uint64_t late_camera_frames = 0;
  uint64_t blobs = 0;
  uint64_t merged_blobs = 0;
  // Marker-frames seen by at least two cameras (reconstructible), out of present marker-frames.
  uint64_t reconstructible = 0;
  uint64_t present = 0;
};

// Free-running cameras (no trigger wire, e.g. USB webcams): each camera exposes at its own
// instants, a random phase within the frame period from the slot's and a rate a little off the
// nominal (the phase drifts by the rate error every frame), and stamps its capture time with
// jitter. Each camera frame keeps the slot its instant lies in (as the node numbers a free-running
// frame); a drift across a slot boundary is wrapped back into the slot, not modelled as the lost
// or doubled frame it would be.
struct FreeRunOptions {
  bool enabled = false;
  double rate_error_ppm = 100.0;  // each camera's rate error, drawn within +-this
  double jitter_ms = 1.0;         // sigma of the capture time stamp's error
  uint64_t seed = 1;

  // Throws std::invalid_argument naming the bad option.
  void Check() const;
};

// Simulated sessions start their trigger clock here (2023-11-14), a plausible wall-clock epoch.
constexpr uint64_t kSimEpochNs = 1700000000000000000ull;

// progress(done, total) is called after each frame when given. Throws std::runtime_error on
// file errors and std::invalid_argument on bad options (a bump of a camera the rig lacks).
ProjectSessionStats ProjectSession(const MarkerTrajectories& motion, const Rig& rig, const ProjectOptions& options,
                                   const std::string& dir,
                                   const std::function<void(size_t, size_t)>& progress = nullptr,
                                   const std::vector<CameraBump>& bumps = {},
                                   const FreeRunOptions& free_run = {});

}  // namespace mocap

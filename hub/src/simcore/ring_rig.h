// A virtual rig: N cameras evenly spaced on a ring around a motion's volume, mounted above it and
// aimed at its centre, with the small placement and lens differences a real installation has.
#pragma once

#include <cstdint>
#include <string>

#include "geometry/camera.h"
#include "simcore/motion_volume.h"

namespace mocap {

struct RingRigOptions {
  int cameras = 8;
  int width = 1280;
  int height = 800;
  double fov_deg = 70.0;            // horizontal field of view
  // Cameras sit this far above the top of the volume (as on a ceiling truss), mm.
  double mount_above_mm = 600.0;
  // Extra distance so the volume does not fill the image edge to edge (1 = just fits).
  double margin = 1.15;
  bool lens_distortion = true;      // wide-angle barrel distortion, different per camera
  bool jitter = true;               // placement / aim / intrinsics differ a little per camera
  uint64_t seed = 1;

  // Throws std::invalid_argument naming the bad option.
  void Check() const;
};

Rig MakeRingRig(const MotionVolume& volume, const RingRigOptions& options);

}  // namespace mocap

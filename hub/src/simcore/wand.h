// `sim wand`: a calibration wand (two markers at a known distance, optionally a third between
// them) waved through the volume a rig sees, as a motion that `sim project`'s faulty projector
// turns into a session; optionally followed by a static L-frame lying on the floor.
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "geometry/camera.h"
#include "io/marker_trajectories.h"
#include "simcore/motion_volume.h"

namespace mocap {

struct WandMotionOptions {
  double wand_length_mm = 500.0;
  double middle_marker_mm = 0.0;  // > 0: a third marker this far from the first end
  int frames = 3000;
  double rate_hz = 100.0;
  double speed_mm_s = 1500.0;     // typical hand speed while waving
  double turn_deg_s = 120.0;      // typical rate at which the wand is turned
  int min_cameras = 0;            // the waved volume is where this many cameras see a point;
                                  // 0 = half the rig (at least 2)
  int up_axis = -1;               // 0/1/2, or -1 to take it from the cameras' viewing directions
  // The first this many frames show only the first end marker W1 (the others are gaps): a
  // single marker waved (`calibrate marker`); the frames after them show the whole wand, which
  // then serves as the scale bar of known length.
  int single_marker_frames = 0;
  int lframe_frames = 0;          // static frames of the L-frame after the wave
  std::vector<Eigen::Vector3d> lframe_markers;  // in the rig's world frame, mm
  uint64_t seed = 1;

  // Throws std::invalid_argument naming the bad option.
  void Check() const;
};

// Where to wave: the box (5th-95th percentile per axis) of points seen by at least min_cameras
// cameras (0 = half the rig, at least 2), limited vertically to 0.6 times
// the cameras' height above their common aim point on either side of it (cameras look down
// at the floor, which they would otherwise count as volume). Throws std::runtime_error when no
// point is seen by enough cameras.
MotionVolume WandVolume(const Rig& rig, int min_cameras, int up_axis);

// Markers W1, W2 (W3 when middle_marker_mm > 0; in wand order: end, middle, end) and L1..Ln for
// the L-frame. The centre sweeps from one random spot of the volume to the next and the wand
// turns smoothly, so that over a few thousand frames every camera sees it across its image at
// many orientations.
MarkerTrajectories MakeWandMotion(const Rig& rig, const WandMotionOptions& options);

}  // namespace mocap

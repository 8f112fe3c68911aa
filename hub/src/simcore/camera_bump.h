// A bumped camera: the simulator's way of moving one camera after calibration (a knock on its
// mount), so a session is seen by the moved camera while the hub keeps the old calibration.
// Pure functions; ParseCameraBump throws std::invalid_argument with the reason.
#pragma once

#include <cstdint>
#include <string>

#include <Eigen/Core>

#include "geometry/camera.h"

namespace mocap {

struct CameraBump {
  uint32_t camera_id = 0;
  double degrees = 0.0;  // rotation about an axis through the camera centre
  double mm = 0.0;       // displacement of the camera centre
  double from_s = 0.0;   // when it happens, seconds after the session's first frame
  uint64_t seed = 1;     // of the rotation axis and displacement direction
};

// "CAM:DEG:MM", e.g. "3:0.5:5" (from_s and seed keep their defaults); throws
// std::invalid_argument naming what is wrong.
CameraBump ParseCameraBump(const std::string& text);

// Rotates the camera by bump.degrees about a random axis through its centre and moves the
// centre by bump.mm in a random direction, both drawn from bump.seed. Throws
// std::invalid_argument when the rig has no camera bump.camera_id. The moved pose is in *rig.
void ApplyCameraBump(const CameraBump& bump, Rig* rig);

// Pose difference of two poses of one camera: centre distance (mm) and rotation angle (deg).
struct PoseChange {
  double centre_mm = 0.0;
  double rotation_deg = 0.0;
};
PoseChange ComparePoses(const Camera& a, const Camera& b);

}  // namespace mocap

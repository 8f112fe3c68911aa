// Test-only synthetic scenes for the calib tests: a ring of cameras with lens distortion looking
// at a volume, and wand frames projected through it with Gaussian centroid noise. (The full
// simulator lives in the sim layer above calib, which calib tests may not use.)
#pragma once

#include <cstdint>
#include <vector>

#include "calib/wand_observations.h"
#include "geometry/camera.h"
#include "ingest/camera_frame.h"

namespace mocap::testing {

// Camera at centre_in_world looking at target_in_world, image y pointing away from world +z.
Camera LookAtCamera(uint32_t id, const Eigen::Vector3d& centre_in_world, const Eigen::Vector3d& target_in_world);

// n cameras on a circle (radius 4 m, heights alternating 2.2 / 2.8 m) aimed near (0, 0, 1 m),
// 1280x800, f = 900 px, barrel distortion.
Rig RingRig(int n, uint32_t seed);

struct WandScene {
  std::vector<FrameSet> frames;
  std::vector<Eigen::Vector3d> wand_centres;  // truth, per frame
};

// Random wand poses in a 3 x 3 x 1.8 m box; markers outside an image or behind a camera are
// not seen; blob order within a camera frame is random.
WandScene MakeWandScene(const Rig& rig, const WandGeometry& wand, int frames, double noise_px, uint32_t seed);

}  // namespace mocap::testing

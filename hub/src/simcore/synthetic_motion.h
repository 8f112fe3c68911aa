// Small self-made motions for tests and benchmarks that must not depend on ../shared/data: a
// person-sized cloud of markers walking a circle, limbs swinging, in a chosen up axis.
#pragma once

#include <cstdint>

#include "io/marker_trajectories.h"

namespace mocap {

struct SyntheticMotionOptions {
  int markers = 30;
  int frames = 120;
  double rate_hz = 120.0;
  int up_axis = 2;                 // 0 = x, 1 = y, 2 = z
  double min_separation_mm = 60.0; // between markers of the rest pose
  uint64_t seed = 1;
  uint64_t first_frame = 0;

  void Check() const;  // throws std::invalid_argument
};

MarkerTrajectories MakeSyntheticMotion(const SyntheticMotionOptions& options);

}  // namespace mocap

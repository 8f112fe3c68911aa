// Rigid bodies added to any motion (sim project --bodies): each body of a bodies file (its
// geometry as given) flies around the subject on a path with fast turns and fast spins, the
// bodies passing close to each other and to the subject, and their markers become columns of the
// scene ("<body>:1", "<body>:2", ...) beside the motion's own. The true poses are kept in the
// bodies' own frames, so that `reconstruct --bodies` with the same file reports comparable poses.
// Paths: around the subject's centroid (followed frame by frame) on a circle whose radius swings
// between `min_radius_mm` and `max_radius_mm`, at `speed_rad_s` with its direction reversed
// every few seconds (a fast turn), the bodies spread in phase and height so that they cross;
// orientation turns at up to `spin_deg_s` about an axis that wanders. Pure.
#pragma once

#include <cstdint>
#include <vector>

#include "bodies/body_definition.h"
#include "bodies/body_trajectories.h"
#include "io/marker_trajectories.h"

namespace mocap {

struct BodySceneOptions {
  double min_radius_mm = 250.0;
  double max_radius_mm = 650.0;
  double speed_rad_s = 2.5;
  double spin_deg_s = 300.0;
  int up_axis = -1;  // of the motion; -1 detects it
  uint64_t seed = 1;
  void Check() const;  // throws std::invalid_argument
};

struct BodyScene {
  MarkerTrajectories scene;        // the motion's markers, then every body's
  std::vector<BodyPoseRow> poses;  // per frame, one true pose per body (tracked)
};

// Throws std::invalid_argument for bad options, an empty motion or no bodies.
BodyScene AddRigidBodies(const MarkerTrajectories& motion, const std::vector<RigidBodyDefinition>& bodies,
                         const BodySceneOptions& options = {});

}  // namespace mocap

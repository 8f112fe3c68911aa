// The cameras a large rig's acquisition matches on first (ReconstructorOptions::seed_cameras):
// a subset spread around the volume, so that every marker stays seen by several of them.
#pragma once

#include <vector>

#include "recon/frame_views.h"

namespace mocap {

// A mask over the rig's cameras with `count` of them set, chosen by farthest-point sampling of
// the camera centres from camera 0 (deterministic; ties go to the lower index). Empty when the
// rig has no more than `count` cameras or count is 0: no subset is needed.
std::vector<char> SpreadCameras(const RigModel& rig, int count);

}  // namespace mocap

// The labelling step shared by `reconstruct --labels` and `labels apply`: reads the marker set,
// names the trajectories in place and returns a one-line report. Errors: std::runtime_error.
#pragma once

#include <string>

#include "io/marker_trajectories.h"

namespace mocap {

// up_axis: 0-2, or -1 to detect it from the data.
std::string ApplyMarkerSet(const std::string& marker_set_path, int up_axis, MarkerTrajectories* markers);

}  // namespace mocap

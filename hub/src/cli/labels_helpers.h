// The naming step shared by `reconstruct --labels` and `labels apply`: reads the marker set and
// names the take in place (pipeline/take_outputs.h); returns the one-line report. Errors
// (an unreadable set, a set that cannot label): std::runtime_error naming the file.
#pragma once

#include <string>

#include "io/marker_trajectories.h"

namespace mocap {

// up_axis: 0-2, or -1 to detect it from the data.
std::string NameTakeFromFile(const std::string& marker_set_path, int up_axis, MarkerTrajectories* markers);

}  // namespace mocap

// Command-line options for the simulated camera faults every session-writing `sim` command shares
// (sim project, sim wand), so their names, help and defaults stay the same.
#pragma once

#include <CLI/CLI.hpp>

#include "simcore/projector.h"

namespace mocap {

// --noise-px --occlusion --occlusion-frames --spurious --drop-frames --marker-mm
void AddCameraFaultOptions(CLI::App* command, ProjectOptions* faults);

}  // namespace mocap

// Helpers shared by the calibration-family commands (sim wand, calibrate ...).
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "ingest/camera_frame.h"

namespace mocap {

// "x,y,z;x,y,z;..." in mm; UsageError naming `option` when malformed or empty.
std::vector<Eigen::Vector3d> ParsePointList(const std::string& text, const std::string& option);

// The session's frames; damage the reader skipped is logged as warnings, not hidden.
std::vector<FrameSet> LoadFramesReporting(const std::string& session);

}  // namespace mocap

// Whole sessions in memory for the offline calibration steps, which need every frame at once
// (static-reflection masks, pairwise statistics, bundle adjustment).
#pragma once

#include <string>
#include <vector>

#include "ingest/camera_frame.h"

namespace mocap {

// Reads every frame set of the session directory in frame order. Throws std::runtime_error
// (naming the directory) when it cannot be opened or holds no frames; damage the reader skipped
// is appended to *warnings when given.
std::vector<FrameSet> LoadSessionFrames(const std::string& dir, std::vector<std::string>* warnings = nullptr);

}  // namespace mocap

// Loads recorded frames (frames.mcf) into memory for timing: a FRAMES_DIR with cam*/
// subdirectories, or one camera directory. Errors throw std::runtime_error with the reason.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace mocap {

struct BenchFrame {
  uint32_t width = 0, height = 0;
  std::vector<uint8_t> pixels;  // width x height, stride = width
  std::string camera;           // directory the frame came from
};

// Reads up to max_frames frames in all (cameras in name order, frames in file order).
// Damaged tails are reported on stderr and the good frames kept.
std::vector<BenchFrame> LoadFrames(const std::string& dir, size_t max_frames);

}  // namespace mocap

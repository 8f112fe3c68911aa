// Writes a synthetic frames directory (DIR/cam1/frames.mcf) of moving marker spots drawn by
// the hub's spot renderer, so the benchmark runs before `mocap-hub sim render` exists.
#pragma once

#include <cstdint>
#include <string>

namespace mocap {

struct MakeFramesOptions {
  uint32_t count = 100;
  uint32_t markers = 45;
  uint32_t width = 1280, height = 800;
  uint64_t seed = 1;
};

// Throws std::runtime_error (std::invalid_argument for bad options). Returns bytes written.
uint64_t MakeFrames(const std::string& dir, const MakeFramesOptions& options);

}  // namespace mocap

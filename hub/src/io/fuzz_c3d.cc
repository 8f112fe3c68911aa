// libFuzzer target: arbitrary bytes as a C3D file. Either a clear error or trajectories whose
// shape adds up; never a crash, and memory bounded by the input's size.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <stdexcept>
#include <vector>

#include "io/c3d.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    const mocap::MarkerTrajectories t = mocap::ParseC3d(std::vector<uint8_t>(data, data + size), "fuzz");
    if (t.points.size() != t.NumFrames() * t.NumMarkers()) std::abort();
    if (t.NumFrames() * t.NumMarkers() * 8 > size) std::abort();  // every point came from the file
  } catch (const std::runtime_error&) {
  }
  return 0;
}

// libFuzzer entry for the live points reader: any bytes must either parse into a consistent
// table or throw runtime_error.
#include <cstddef>
#include <cstdint>
#include <sstream>
#include <stdexcept>
#include <string>

#include "io/live_points.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
  try {
    const mocap::MarkerTrajectories result = mocap::ParseLivePoints(in, "fuzz");
    if (result.points.size() != result.NumFrames() * result.NumMarkers()) __builtin_trap();
  } catch (const std::runtime_error&) {
  }
  return 0;
}

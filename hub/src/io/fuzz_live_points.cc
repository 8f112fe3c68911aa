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
    const mocap::LivePoints live = mocap::ParseLivePoints(in, "fuzz");
    const mocap::MarkerTrajectories& result = live.points;
    if (result.points.size() != result.NumFrames() * result.NumMarkers()) __builtin_trap();
    if (live.identity.track.size() != result.points.size() || live.identity.name.size() != result.points.size())
      __builtin_trap();
    for (int32_t name : live.identity.name) {
      if (name < -1 || name >= static_cast<int32_t>(live.identity.names.size())) __builtin_trap();
    }
  } catch (const std::runtime_error&) {
  }
  return 0;
}

// libFuzzer entry for the TRC parser: any bytes must either parse or throw runtime_error.
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>

#include "io/trc.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const mocap::MarkerTrajectories result = mocap::ParseTrc(text, "fuzz");
    if (result.points.size() != result.NumFrames() * result.NumMarkers()) __builtin_trap();
  } catch (const std::runtime_error&) {
  }
  return 0;
}

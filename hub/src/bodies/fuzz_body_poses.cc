// libFuzzer entry for the body pose file reader: any bytes must load or throw runtime_error.
#include <cstddef>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>

#include "bodies/body_trajectories.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    const auto rows = mocap::ParseBodyPoses(std::string(reinterpret_cast<const char*>(data), size), "fuzz");
    for (const auto& r : rows)
      if ((r.tracked || r.predicted) && !(std::abs(r.orientation.norm() - 1.0) < 1e-6)) __builtin_trap();
  } catch (const std::runtime_error&) {
  }
  return 0;
}

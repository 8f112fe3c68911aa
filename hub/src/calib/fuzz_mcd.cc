// libFuzzer entry for seed 000's .mcd parser (with its Tsai blocks): any bytes must either parse
// into frames holding one camera frame per camera, or throw runtime_error.
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>

#include "calib/mcd.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const mocap::McdRecording recording = mocap::ParseMcd(text, "fuzz");
    for (const mocap::FrameSet& set : recording.frames) {
      if (set.cameras.size() != recording.cameras.size()) __builtin_trap();
    }
  } catch (const std::runtime_error&) {
  }
  return 0;
}

// libFuzzer entry for the calibration JSON reader: any bytes must load or throw runtime_error.
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>

#include <nlohmann/json.hpp>

#include "io/calibration_json.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const nlohmann::json document = nlohmann::json::parse(data, data + size, nullptr, /*allow_exceptions=*/false);
  if (document.is_discarded()) return 0;
  try {
    const mocap::Rig rig = mocap::RigFromJson(document, "fuzz");
    // A rig that loads must survive being written and read back.
    const mocap::Rig again = mocap::RigFromJson(mocap::RigToJson(rig), "fuzz-again");
    if (again.cameras.size() != rig.cameras.size()) __builtin_trap();
  } catch (const std::runtime_error&) {
  }
  return 0;
}

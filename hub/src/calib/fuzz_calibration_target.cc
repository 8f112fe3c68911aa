// libFuzzer entry for the calibration target's JSON reader: any bytes that parse as JSON must
// either give a layout that passes Check() (with a page no larger than 2 m) or throw
// runtime_error.
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>

#include <nlohmann/json.hpp>

#include "calib/calibration_target.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  nlohmann::json document;
  try {
    document = nlohmann::json::parse(reinterpret_cast<const char*>(data), reinterpret_cast<const char*>(data) + size);
  } catch (const nlohmann::json::exception&) {
    return 0;
  }
  try {
    const mocap::CalibrationTargetLayout layout = mocap::TargetFromJson(document, "fuzz");
    layout.Check();
    if (layout.PageWidthMm() > 2000.0 || layout.PageHeightMm() > 2000.0) __builtin_trap();
    const Eigen::Vector3d last = layout.PointInWorld(layout.NumPoints() - 1);
    if (!last.allFinite()) __builtin_trap();
  } catch (const std::runtime_error&) {
  }
  return 0;
}

// The calibration file serve runs with, replaced by an applied wanding or a camera's re-solve:
// every old file stays beside the new one, named by when it was replaced, so that an operator
// can go back to any of them (and an unwanted apply overwrites none).
#pragma once

#include <cstdint>
#include <string>

#include <nlohmann/json.hpp>

namespace mocap::service {

// PATH.2026-11-27T230704Z (UTC at now_ns; -2, -3, ... when that exists): where an applied
// calibration keeps the file it replaces.
std::string DatedCopyName(const std::string& path, uint64_t now_ns);

// Copies PATH to DatedCopyName(PATH, now_ns), then writes the document to PATH. Throws
// ApiError 500 with the reason when either fails (the old file is then untouched).
void ReplaceCalibrationKeepingOld(const std::string& path, const nlohmann::json& document, uint64_t now_ns);

}  // namespace mocap::service

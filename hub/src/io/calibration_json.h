// Calibration / rig file (DESIGN.md JSON: millimetres, OpenCV conventions) to and from Rig.
// Error policy of the io layer: readers and writers throw std::runtime_error whose message
// names the file and the reason in one line ("rig.json: camera 2: fx must be > 0"); the CLI
// prints it and exits non-zero. Unknown fields are ignored so other tools may add their own.
#pragma once

#include <string>

#include <nlohmann/json_fwd.hpp>

#include "geometry/camera.h"

namespace mocap {

Rig LoadRigJson(const std::string& path);
void SaveRigJson(const Rig& rig, const std::string& path);

// The same conversions without files, for callers that embed a rig in another document
// (session.json). `source` names the origin in error messages.
Rig RigFromJson(const nlohmann::json& document, const std::string& source);
nlohmann::json RigToJson(const Rig& rig);

// `document` (a calibration JSON) with camera.id's rotation and translation replaced by
// camera's; every other field and camera stays as written. Throws std::runtime_error when the
// document has no camera of that id.
nlohmann::json WithCameraPose(nlohmann::json document, const Camera& camera);

}  // namespace mocap

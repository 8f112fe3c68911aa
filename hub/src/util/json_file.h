// Every JSON file the hub reads or writes (calibrations, session.json, reports, masks) goes
// through these two functions, so there is one durability rule and one error style:
// - writing: a temporary file beside the target is written and fsync'ed, renamed over the target
//   and the directory fsync'ed; a reader never sees a half-written file, and a failed write
//   leaves the old file (or none) in place and no temporary behind;
// - errors: std::runtime_error "<path>: <what>" (with the parse error's byte position).
#pragma once

#include <string>

#include <nlohmann/json.hpp>

namespace mocap {

nlohmann::json ReadJsonFile(const std::string& path);

// Creates the parent directory when it is missing. indent: as nlohmann::json::dump.
void WriteJsonFile(const nlohmann::json& document, const std::string& path, int indent = 2);

// Any other text file the hub writes (reports) under the same rule.
void WriteTextFile(const std::string& text, const std::string& path);

}  // namespace mocap

// Every JSON file the hub reads or writes (calibrations, session.json, reports, masks) goes
// through these two functions, so there is one durability rule and one error style:
// - writing: a temporary file beside the target is written and fsync'ed, renamed over the target
//   and the directory fsync'ed; a reader never sees a half-written file, and a failed write
//   leaves the old file (or none) in place and no temporary behind;
// - reading: only a regular file of at most kMaxJsonFileBytes is read (util/regular_file.h), so a
//   path naming /dev/zero or a FIFO is refused at once instead of growing or waiting for ever;
// - errors: std::runtime_error "<path>: <what>" (with the parse error's byte position).
#pragma once

#include <cstddef>
#include <string>

#include <nlohmann/json.hpp>

namespace mocap {

// The bound on a JSON file read. The hub's JSON files are small: a 32-camera rig is 27 KB and a
// wand calibration adds about 1 KB of report per camera, session.json is under 1 KiB plus what a
// caller adds to it, masks, bodies and marker sets a few KiB. 16 MiB leaves two orders of
// magnitude over any of them and keeps the parsed document (several times the text) in memory.
constexpr size_t kMaxJsonFileBytes = size_t{16} << 20;

nlohmann::json ReadJsonFile(const std::string& path);

// Creates the parent directory when it is missing. indent: as nlohmann::json::dump.
void WriteJsonFile(const nlohmann::json& document, const std::string& path, int indent = 2);

// Any other text file the hub writes (reports) under the same rule.
void WriteTextFile(const std::string& text, const std::string& path);

}  // namespace mocap

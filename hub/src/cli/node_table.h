// `mocap-hub nodes`: one line per node of GET /api/nodes (the service's node JSON, hub_json.cc).
#pragma once

#include <string>

#include <nlohmann/json.hpp>

namespace mocap {

// A field of the service's JSON as table text: strings as they are, null or absent "-".
std::string JsonFieldText(const nlohmann::json& j, const char* key);

std::string NodeTableHeader();
// Throws nlohmann::json's errors for a node object without the service's fields.
std::string NodeTableRow(const nlohmann::json& node);

}  // namespace mocap

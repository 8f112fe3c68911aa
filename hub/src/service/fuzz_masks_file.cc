// libFuzzer entry for the installation's masks file (serve --masks-file): any JSON must load or
// throw runtime_error; masks that load must be written and read back unchanged and turn into the
// node's mask commands as serve sends them when a node joins (or be refused as MaskCommands
// documents), every command within the node's limits.
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <vector>

#include <nlohmann/json.hpp>

#include "service/auto_mask.h"

namespace {

namespace s = mocap::service;

bool Same(const s::CameraMask& a, const s::CameraMask& b) {
  if (a.camera_id != b.camera_id || a.width != b.width || a.height != b.height || a.frames != b.frames ||
      a.regions != b.regions || a.blobs.size() != b.blobs.size())
    return false;
  for (size_t i = 0; i < a.blobs.size(); ++i)
    if (a.blobs[i].x != b.blobs[i].x || a.blobs[i].y != b.blobs[i].y || a.blobs[i].radius_px != b.blobs[i].radius_px ||
        a.blobs[i].presence != b.blobs[i].presence)
      return false;
  return true;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const nlohmann::json document = nlohmann::json::parse(data, data + size, nullptr, /*allow_exceptions=*/false);
  if (document.is_discarded()) return 0;
  std::vector<s::CameraMask> masks;
  try {
    masks = s::MasksFromJson(document, "fuzz");
  } catch (const std::runtime_error&) {
    return 0;
  }
  const std::vector<s::CameraMask> again = s::MasksFromJson(s::MasksToJson(masks), "again");
  if (again.size() != masks.size()) __builtin_trap();
  for (size_t i = 0; i < masks.size(); ++i)
    if (!Same(masks[i], again[i])) __builtin_trap();
  const s::NodeMaskLimits limits;
  for (const s::CameraMask& mask : masks) {
    std::vector<mocap::v1::Control> commands;
    try {
      commands = s::MaskCommands(mask, limits);
    } catch (const std::invalid_argument&) {
      continue;
    }
    if (commands.empty() || commands.size() > limits.max_chunks) __builtin_trap();
    for (const mocap::v1::Control& c : commands)
      if (static_cast<size_t>(c.set_mask().rects_size()) > limits.max_rects ||
          c.set_mask().bits().size() > limits.chunk_bytes)
        __builtin_trap();
  }
  return 0;
}

// libFuzzer target: arbitrary bytes as a wire key file; a file either parses into a node id and
// one or two distinct keys that format and parse back the same, or is refused naming it.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <stdexcept>
#include <string>

#include "wire/key_file.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace mocap::wire;
  KeyFile file;
  try {
    file = ParseKeyFile(std::string(reinterpret_cast<const char*>(data), size), "fuzz.key");
  } catch (const std::invalid_argument& e) {
    if (std::string(e.what()).rfind("fuzz.key", 0) != 0) std::abort();
    return 0;
  }
  if (file.node_id < 1 || file.node_id > 4095 || file.keys.empty() || file.keys.size() > kMaxKeysPerFile)
    std::abort();
  const KeyFile back = ParseKeyFile(FormatKeyFile(file), "formatted");
  if (back.node_id != file.node_id || back.keys.size() != file.keys.size()) std::abort();
  for (size_t i = 0; i < file.keys.size(); ++i)
    if (back.keys[i].id != file.keys[i].id || back.keys[i].key != file.keys[i].key) std::abort();
  return 0;
}

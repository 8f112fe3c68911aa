// libFuzzer entry for the .mot reader: any bytes parse or throw runtime_error, and a table that
// parses has rows as wide as its column names.
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>

#include "skeleton/motion_files.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    const mocap::MotTable table = mocap::ParseMot(std::string(reinterpret_cast<const char*>(data), size), "fuzz");
    for (const auto& row : table.rows)
      if (row.size() != table.columns.size()) __builtin_trap();
  } catch (const std::runtime_error&) {
  }
  return 0;
}

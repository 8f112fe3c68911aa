// libFuzzer entry for serve's config file (hub.conf): any bytes as the file, read and given to
// the real serve command's options, must apply or be refused with the file's name as
// ReadConfigFile / ApplyConfigFile document (runtime_error for the file, UsageError for a key or
// value); entries read must be trimmed keys on increasing lines.
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>

#include <CLI/CLI.hpp>

#include "cli/commands.h"
#include "cli/config_file.h"
#include "util/fuzz_scratch_file.h"

namespace {

bool StartsWith(const std::string& text, const std::string& prefix) { return text.compare(0, prefix.size(), prefix) == 0; }

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const mocap::FuzzScratchFile scratch("hub.conf");
  const std::string& path = scratch.Write(data, size);
  std::vector<mocap::ConfigEntry> entries;
  try {
    entries = mocap::ReadConfigFile(path);
  } catch (const std::runtime_error& e) {
    if (!StartsWith(e.what(), path + ":")) __builtin_trap();
    return 0;
  }
  int last_line = 0;
  for (const mocap::ConfigEntry& e : entries) {
    if (e.line <= last_line || e.key.empty() || e.key.find('=') != std::string::npos ||
        e.key.find_first_of(" \t\r") == 0 || e.key.find_last_of(" \t\r") == e.key.size() - 1)
      __builtin_trap();
    last_line = e.line;
  }
  CLI::App app;
  mocap::AddServeCommand(app);
  try {
    mocap::ApplyConfigFile(*app.get_subcommand("serve"), path);
  } catch (const mocap::UsageError& e) {
    if (!StartsWith(e.what(), path + ":")) __builtin_trap();
  }
  return 0;
}

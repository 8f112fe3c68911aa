// Config files for long-running commands (`serve --config FILE`): one `key = value` per line,
// keys being the command's long option names without the dashes, `#` comments, blank lines;
// values may be quoted. (CLI11 2.1, Debian bookworm's, reads config files for the top-level app
// only, so the subcommand's file is read here and fed through its own options.)
#pragma once

#include <string>
#include <vector>

#include <CLI/CLI.hpp>

namespace mocap {

struct ConfigEntry {
  int line = 0;
  std::string key;
  std::string value;
};

// Throws std::runtime_error "<path>:<line>: <why>" on unreadable files and malformed lines, and
// "<path>: <why>" for anything but a regular file of at most 64 KiB.
std::vector<ConfigEntry> ReadConfigFile(const std::string& path);

// Gives each entry to the command's option of that name, unless the command line set it (flags
// win); the option's own checks apply. Throws UsageError "<path>:<line>: <why>" for unknown keys
// and refused values.
void ApplyConfigFile(CLI::App& command, const std::string& path);

}  // namespace mocap

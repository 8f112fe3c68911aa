// key = value config files (see config_file.h).
#include "cli/config_file.h"

#include <map>
#include <sstream>
#include <stdexcept>

#include "cli/commands.h"
#include "util/regular_file.h"

namespace mocap {
namespace {

constexpr size_t kMaxConfigBytes = 64 * 1024;

std::string Trim(const std::string& s) {
  const size_t first = s.find_first_not_of(" \t\r");
  if (first == std::string::npos) return "";
  return s.substr(first, s.find_last_not_of(" \t\r") - first + 1);
}

}  // namespace

std::vector<ConfigEntry> ReadConfigFile(const std::string& path) {
  // Read whole and bounded before any line is looked at: getline on /dev/zero (which --config's
  // existing-file check lets through) grew one line without end, and a FIFO never ended.
  const std::string bytes = ReadRegularFile(path, kMaxConfigBytes, "a config file");
  std::istringstream in(bytes);
  std::vector<ConfigEntry> entries;
  std::string text;
  int number = 0;
  while (std::getline(in, text)) {
    ++number;
    if (number > 10000 || text.size() > 4096) throw std::runtime_error(path + ":" + std::to_string(number) + ": too long");
    const std::string line = Trim(text);
    if (line.empty() || line[0] == '#') continue;
    const size_t eq = line.find('=');
    if (eq == std::string::npos)
      throw std::runtime_error(path + ":" + std::to_string(number) + ": expected `key = value`");
    ConfigEntry entry{number, Trim(line.substr(0, eq)), Trim(line.substr(eq + 1))};
    if (entry.key.empty()) throw std::runtime_error(path + ":" + std::to_string(number) + ": no key before '='");
    if (entry.value.size() >= 2 && entry.value.front() == '"' && entry.value.back() == '"')
      entry.value = entry.value.substr(1, entry.value.size() - 2);
    entries.push_back(entry);
  }
  return entries;
}

void ApplyConfigFile(CLI::App& command, const std::string& path) {
  std::map<std::string, int> line_of_key;
  for (const ConfigEntry& e : ReadConfigFile(path)) {
    const std::string where = path + ":" + std::to_string(e.line) + ": ";
    CLI::Option* option = e.key == "config" ? nullptr : command.get_option_no_throw("--" + e.key);
    if (!option) throw UsageError(where + "unknown key '" + e.key + "' (see " + command.get_name() + " --help)");
    // A second line for a key would count as given on the command line and be dropped unseen.
    const auto [first, fresh] = line_of_key.emplace(e.key, e.line);
    if (!fresh) throw UsageError(where + "'" + e.key + "' is set already on line " + std::to_string(first->second));
    if (option->count() > 0) continue;  // given on the command line
    try {
      option->add_result(e.value);
      option->run_callback();
    } catch (const CLI::Error& error) {
      throw UsageError(where + error.what());
    }
  }
}

}  // namespace mocap

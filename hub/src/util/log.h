// The hub's one logging module: spdlog, to stderr (systemd's journal takes it), one level for the
// whole process, set by `mocap-hub --log-level`. Diagnostics (progress of a live command, warnings
// about data that was skipped) go through it; results go to stdout from cli/ only. Libraries
// return errors (exceptions at their boundary, or report fields) and may log at debug level; they
// never print. Lines read "mocap-hub: <level>: <text>".
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <utility>

#include <spdlog/spdlog.h>

namespace mocap::log {

enum class Level { kTrace, kDebug, kInfo, kWarn, kError, kOff };

// "trace", "debug", "info", "warn" (or "warning"), "error", "off"; nullopt for anything else.
std::optional<Level> ParseLevel(const std::string& name);
const char* LevelName(Level level);

// The process-wide level (default: info).
void SetLevel(Level level);
Level GetLevel();

// Sends the log to `sink` instead of stderr (tests); nullptr restores stderr.
void SetSink(std::shared_ptr<spdlog::sinks::sink> sink);

template <typename... Args>
void Debug(spdlog::format_string_t<Args...> format, Args&&... args) {
  spdlog::debug(format, std::forward<Args>(args)...);
}
template <typename... Args>
void Info(spdlog::format_string_t<Args...> format, Args&&... args) {
  spdlog::info(format, std::forward<Args>(args)...);
}
template <typename... Args>
void Warn(spdlog::format_string_t<Args...> format, Args&&... args) {
  spdlog::warn(format, std::forward<Args>(args)...);
}
template <typename... Args>
void Error(spdlog::format_string_t<Args...> format, Args&&... args) {
  spdlog::error(format, std::forward<Args>(args)...);
}

}  // namespace mocap::log

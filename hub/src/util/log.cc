#include "util/log.h"

#include <spdlog/sinks/stdout_sinks.h>

namespace mocap::log {
namespace {

struct LevelEntry {
  Level level;
  const char* name;
  spdlog::level::level_enum spd;
};

constexpr LevelEntry kLevels[] = {
    {Level::kTrace, "trace", spdlog::level::trace}, {Level::kDebug, "debug", spdlog::level::debug},
    {Level::kInfo, "info", spdlog::level::info},    {Level::kWarn, "warn", spdlog::level::warn},
    {Level::kError, "error", spdlog::level::err},   {Level::kOff, "off", spdlog::level::off},
};

const LevelEntry& EntryOf(Level level) {
  for (const LevelEntry& entry : kLevels)
    if (entry.level == level) return entry;
  return kLevels[2];
}

Level g_level = Level::kInfo;
bool g_installed = false;

// Builds the process's logger on first use: stderr unless a sink is given, the hub's line format.
void Install(std::shared_ptr<spdlog::sinks::sink> sink) {
  if (!sink) sink = std::make_shared<spdlog::sinks::stderr_sink_mt>();
  auto logger = std::make_shared<spdlog::logger>("mocap-hub", std::move(sink));
  logger->set_pattern("mocap-hub: %l: %v");
  logger->set_level(EntryOf(g_level).spd);
  logger->flush_on(spdlog::level::trace);  // a diagnostic is worth nothing if a crash eats it
  spdlog::set_default_logger(std::move(logger));
  g_installed = true;
}

}  // namespace

std::optional<Level> ParseLevel(const std::string& name) {
  if (name == "warning") return Level::kWarn;
  for (const LevelEntry& entry : kLevels)
    if (name == entry.name) return entry.level;
  return std::nullopt;
}

const char* LevelName(Level level) { return EntryOf(level).name; }

void SetLevel(Level level) {
  g_level = level;
  if (!g_installed) Install(nullptr);
  spdlog::set_level(EntryOf(level).spd);
}

Level GetLevel() { return g_level; }

void SetSink(std::shared_ptr<spdlog::sinks::sink> sink) { Install(std::move(sink)); }

}  // namespace mocap::log

#include "util/log.h"

#include <memory>
#include <sstream>
#include <string>

#include <gtest/gtest.h>
#include <spdlog/sinks/ostream_sink.h>

namespace mocap {
namespace {

TEST(Log, LevelNamesRoundTrip) {
  for (log::Level level : {log::Level::kTrace, log::Level::kDebug, log::Level::kInfo, log::Level::kWarn,
                           log::Level::kError, log::Level::kOff}) {
    EXPECT_EQ(log::ParseLevel(log::LevelName(level)), level);
  }
  EXPECT_EQ(log::ParseLevel("warning"), log::Level::kWarn);
  EXPECT_FALSE(log::ParseLevel("loud").has_value());
  EXPECT_FALSE(log::ParseLevel("").has_value());
}

TEST(Log, LinesBelowTheLevelAreDroppedAndTheFormatIsTheHubs) {
  std::ostringstream out;
  log::SetSink(std::make_shared<spdlog::sinks::ostream_sink_mt>(out));
  log::SetLevel(log::Level::kWarn);
  log::Info("hidden {}", 1);
  log::Warn("shown {} of {}", 2, 3);
  log::Error("also shown");
  EXPECT_EQ(out.str(), "mocap-hub: warning: shown 2 of 3\nmocap-hub: error: also shown\n");

  out.str("");
  log::SetLevel(log::Level::kOff);
  log::Error("nothing");
  EXPECT_EQ(out.str(), "");
  EXPECT_EQ(log::GetLevel(), log::Level::kOff);

  log::SetLevel(log::Level::kDebug);
  log::Debug("detail");
  EXPECT_EQ(out.str(), "mocap-hub: debug: detail\n");
  log::SetSink(nullptr);
  log::SetLevel(log::Level::kInfo);
}

}  // namespace
}  // namespace mocap

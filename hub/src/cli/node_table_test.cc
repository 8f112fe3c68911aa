// The node table: a running node that has sent nothing yet says it waits for the trigger instead
// of showing zeros; once frames flow (or when it is not running) the figures are shown.
#include "cli/node_table.h"

#include <string>

#include <gtest/gtest.h>

namespace mocap {
namespace {

nlohmann::json Node(const std::string& state, unsigned long long sent) {
  return {{"id", 3},          {"address", "10.0.0.3:5000"}, {"state", state},       {"firmware", "1.2.0"},
          {"fps", 239.96},    {"detect_us_mean", 412},      {"frames_sent", sent},  {"frames_dropped", 2},
          {"threshold", 180}, {"temperature_c", 51.25},     {"last_seen_s", 0.04},  {"masked", false},
          {"sync", {{"edge_jitter_ns", 850}}}};
}

TEST(NodeTable, ARunningNodeBeforeItsFirstFrameWaitsForTheTrigger) {
  nlohmann::json n = Node("running", 0);
  n["fps"] = 0.0;
  n["detect_us_mean"] = 0;
  const std::string row = NodeTableRow(n);
  EXPECT_NE(row.find("waiting for the first trigger"), std::string::npos) << row;
  EXPECT_EQ(row.find("   0.0  "), std::string::npos) << row;  // no zero rate
  EXPECT_EQ(row.find("0us"), std::string::npos) << row;
}

TEST(NodeTable, FramesFlowingShowTheirFigures) {
  const std::string row = NodeTableRow(Node("running", 9600));
  EXPECT_EQ(row.find("waiting"), std::string::npos) << row;
  EXPECT_NE(row.find("240.0"), std::string::npos) << row;
  EXPECT_NE(row.find("412us"), std::string::npos) << row;
  EXPECT_NE(row.find("9600"), std::string::npos) << row;
  EXPECT_NE(row.find("51.2"), std::string::npos) << row;
  // An idle node that never sent is not waiting for a trigger.
  EXPECT_EQ(NodeTableRow(Node("idle", 0)).find("waiting"), std::string::npos);
}

TEST(NodeTable, TheHeaderAndARowLineUp) {
  const std::string header = NodeTableHeader(), row = NodeTableRow(Node("running", 9600));
  EXPECT_EQ(header.find("fps") + 3, row.find("240.0") + 5);  // right-aligned under "fps"
}

}  // namespace
}  // namespace mocap

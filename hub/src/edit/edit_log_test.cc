// Reading edit logs: every operation and field read as written and written back the same; bad
// logs refused with the operation, field and rule named. The fuzz corpus (tests/fuzz/corpus/
// edit_log) is replayed here too, so the plain build runs it.
#include "edit/edit_log.h"

#include <dirent.h>

#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

namespace mocap::edit {
namespace {

std::string Log(const std::string& operations) {
  return R"({"format": "mocap-edits", "version": 1, "operations": )" + operations + "}";
}

std::string Refusal(const std::string& text) {
  try {
    ParseEditLog(text, "edits.json");
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

TEST(EditLog, ReadsEveryOperationAndWritesItBack) {
  const EditLog log = ParseEditLog(Log(R"([
      {"op": "fill", "marker": "LKNE", "method": "pattern", "donors": ["LANK"], "from": 10, "to": 90, "max_gap": 50},
      {"op": "fill", "marker": "LKNE", "method": "spline", "context": 20},
      {"op": "swap", "markers": ["A", "B"], "from": 5, "to": 5},
      {"op": "split", "marker": "A", "frame": 300, "name": "A.2"},
      {"op": "join", "marker": "A", "other": "A.2"},
      {"op": "rename", "marker": "M004", "name": "R ASIS"},
      {"op": "delete", "marker": "M009"},
      {"op": "spikes", "markers": ["A"], "threshold": 6.5, "remove": true}])"),
                                   "edits.json");
  ASSERT_EQ(log.operations.size(), 8u);
  const EditOperation& fill = log.operations[0];
  EXPECT_EQ(fill.kind, EditKind::kFill);
  EXPECT_EQ(fill.method, FillMethod::kPattern);
  EXPECT_EQ(fill.markers, std::vector<std::string>{"LANK"});
  EXPECT_TRUE(fill.has_range);
  EXPECT_EQ(fill.from, 10u);
  EXPECT_EQ(fill.to, 90u);
  EXPECT_EQ(fill.max_gap, 50);
  EXPECT_EQ(log.operations[1].context, 20);
  EXPECT_FALSE(log.operations[1].has_range);
  EXPECT_EQ(log.operations[2].other, "B");
  EXPECT_EQ(log.operations[3].frame, 300u);
  EXPECT_EQ(log.operations[3].other, "A.2");
  EXPECT_EQ(log.operations[5].other, "R ASIS");
  EXPECT_EQ(log.operations[6].kind, EditKind::kDelete);
  EXPECT_DOUBLE_EQ(log.operations[7].threshold, 6.5);
  EXPECT_TRUE(log.operations[7].remove);
  const nlohmann::json written = EditLogToJson(log);
  EXPECT_EQ(EditLogToJson(EditLogFromJson(written, "again")), written);
  EXPECT_TRUE(ParseEditLog(Log("[]"), "empty").operations.empty());
}

TEST(EditLog, RefusalsNameTheOperationFieldAndRule) {
  const struct {
    std::string text, expected;
  } cases[] = {
      {"[", "edits.json: not JSON"},
      {R"({"format": "mocap-edits", "version": 2, "operations": []})", "'version' must be 1"},
      {R"({"format": "x", "version": 1, "operations": []})", "'format' must be \"mocap-edits\""},
      {R"({"format": "mocap-edits", "version": 1, "operations": [], "extra": 1})", "'extra' is not an edit log field"},
      {Log(R"([{"op": "paint"}])"), "operation 1: field 'op' must be one of"},
      {Log(R"([{"op": "fill", "marker": "A"}])"), "operation 1 (fill): field 'method' is missing"},
      {Log(R"([{"op": "fill", "marker": "A", "method": "cubic"}])"), "field 'method' must be one of linear, pattern"},
      {Log(R"([{"op": "delete", "marker": "A", "from": 3}])"), "field 'to' is missing"},
      {Log(R"([{"op": "delete", "marker": "A", "from": 9, "to": 3}])"), "field 'to' 3 is before 'from' 9"},
      {Log(R"([{"op": "delete", "marker": "A", "from": -1, "to": 3}])"), "field 'from' must be a frame number"},
      {Log(R"([{"op": "delete", "marker": "A", "from": 1.5, "to": 3}])"), "field 'from' must be a frame number"},
      {Log(R"([{"op": "swap", "markers": ["A"]}])"), "field 'markers' must be a list of 2-2 marker names"},
      {Log(R"([{"op": "swap", "markers": ["A", "A"]}])"), "names 'A' twice"},
      {Log(R"([{"op": "rename", "marker": "A", "name": "B\tC"}])"), "field 'name' 'B\tC' holds a control character"},
      {Log(R"([{"op": "rename", "marker": "A", "name": ""}])"), "field 'name' must be a marker name of 1-255 bytes"},
      {Log(R"([{"op": "rename", "marker": "A", "name": "B", "frame": 3}])"), "field 'frame' is not a field of this operation"},
      {Log(R"([{"op": "spikes", "threshold": 1}])"), "field 'threshold' must be a number 2-1000"},
      {Log(R"([{"op": "spikes", "remove": "yes"}])"), "field 'remove' must be true or false"},
      {Log(R"([{"op": "join", "marker": "A", "other": "A"}])"), "field 'other' is the marker itself"},
      {Log(R"([{"op": "fill", "marker": "A", "method": "spline", "context": 1}])"), "field 'context' must be a whole number 2-1000"},
      {Log(R"([{"op": "rename", "marker": "A", "name": "B"}, 7])"), "operation 2: an operation is a JSON object"},
  };
  for (const auto& c : cases) {
    const std::string refusal = Refusal(c.text);
    EXPECT_NE(refusal.find(c.expected), std::string::npos) << c.text << "\n -> " << refusal;
  }
}

TEST(EditLog, ReadsFilesWithABound) {
  EXPECT_THROW(ReadEditLog("/dev/zero"), std::runtime_error);
  const std::string path = ::testing::TempDir() + "/edits.json";
  std::ofstream(path) << Log(R"([{"op": "delete", "marker": "A"}])");
  EXPECT_EQ(ReadEditLog(path).operations.size(), 1u);
}

// Every corpus file either reads or is refused with std::invalid_argument; one that reads writes
// back to JSON that reads the same.
TEST(EditLog, FuzzCorpusReplays) {
  const std::string dir = MOCAP_EDIT_CORPUS;
  DIR* d = opendir(dir.c_str());
  ASSERT_NE(d, nullptr) << dir;
  size_t files = 0, accepted = 0;
  while (const dirent* entry = readdir(d)) {
    if (entry->d_name[0] == '.') continue;
    std::ifstream in(dir + "/" + entry->d_name, std::ios::binary);
    std::stringstream text;
    text << in.rdbuf();
    ++files;
    try {
      const nlohmann::json written = EditLogToJson(ParseEditLog(text.str(), entry->d_name));
      EXPECT_EQ(EditLogToJson(EditLogFromJson(written, "again")), written) << entry->d_name;
      ++accepted;
    } catch (const std::invalid_argument&) {
    }
  }
  closedir(d);
  EXPECT_GE(files, 5u);
  EXPECT_GE(accepted, 2u);
}

}  // namespace
}  // namespace mocap::edit

#include "util/json_file.h"

#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

#include "util/special_file_testing.h"
#include "util/temporary_directory_testing.h"

namespace mocap {
namespace {

namespace fs = std::filesystem;

class JsonFileTest : public ::testing::Test {
 protected:
  std::string Path(const std::string& name) const { return dir_.File(name); }
  static std::string Slurp(const std::string& path) {
    std::ifstream in(path);
    return std::string(std::istreambuf_iterator<char>(in), {});
  }
  static std::string ErrorOf(const std::function<void()>& action) {
    try {
      action();
    } catch (const std::runtime_error& error) {
      return error.what();
    }
    return "";
  }
  const testing::TemporaryDirectory dir_{"json_file_test"};
};

TEST_F(JsonFileTest, RoundTripsAndReplacesTheTarget) {
  const std::string path = Path("sub/doc.json");
  WriteJsonFile({{"a", 1}}, path);
  WriteJsonFile({{"a", 2}, {"b", "x"}}, path);
  const nlohmann::json back = ReadJsonFile(path);
  EXPECT_EQ(back["a"], 2);
  EXPECT_EQ(back["b"], "x");
  EXPECT_FALSE(fs::exists(path + ".tmp"));
}

TEST_F(JsonFileTest, FailedWriteLeavesTheOldFileAndNoTemporary) {
  const std::string path = Path("doc.json");
  WriteJsonFile({{"version", 1}}, path);
  const std::string before = Slurp(path);
  // Invalid UTF-8 cannot be serialised: the write must fail before touching the target.
  const std::string error = ErrorOf([&] { WriteJsonFile({{"bad", std::string("\xff\xfe")}}, path); });
  EXPECT_NE(error.find(path), std::string::npos) << error;
  EXPECT_EQ(Slurp(path), before);
  EXPECT_FALSE(fs::exists(path + ".tmp"));
}

TEST_F(JsonFileTest, UnwritableDirectoryIsAnErrorNamingTheFile) {
  if (::geteuid() == 0) {
    // root ignores directory permissions; a path under a regular file fails for everyone.
    std::ofstream(Path("plain")) << "x";
    const std::string path = Path("plain/doc.json");
    const std::string error = ErrorOf([&] { WriteJsonFile({{"a", 1}}, path); });
    EXPECT_NE(error.find(path), std::string::npos) << error;
    EXPECT_FALSE(fs::exists(path));
    return;
  }
  fs::create_directories(dir_.path() / "locked");
  fs::permissions(dir_.path() / "locked", fs::perms::owner_read | fs::perms::owner_exec);
  const std::string path = Path("locked/doc.json");
  const std::string error = ErrorOf([&] { WriteJsonFile({{"a", 1}}, path); });
  EXPECT_NE(error.find(path), std::string::npos) << error;
  EXPECT_FALSE(fs::exists(path));
}

TEST_F(JsonFileTest, ReadErrorsNameTheFileAndThePosition) {
  const std::string missing = Path("missing.json");
  EXPECT_NE(ErrorOf([&] { ReadJsonFile(missing); }).find(missing + ": cannot open"), std::string::npos);
  const std::string broken = Path("broken.json");
  std::ofstream(broken) << "{\"a\": 1,,}";
  const std::string error = ErrorOf([&] { ReadJsonFile(broken); });
  EXPECT_NE(error.find(broken + ": not valid JSON at byte 9"), std::string::npos) << error;
  // A number past a double's range is an out_of_range error of the parser, not a parse error: it
  // escaped as a JSON exception from every file read here (the session.json fuzzer's seeded run).
  std::ofstream(broken) << "{\"rate_hz\": 4444e444444}";
  const std::string overflow = ErrorOf([&] { ReadJsonFile(broken); });
  EXPECT_NE(overflow.find(broken + ": not valid JSON ("), std::string::npos) << overflow;
  EXPECT_NE(overflow.find("number overflow"), std::string::npos) << overflow;
}

// Only regular files are read, and only up to kMaxJsonFileBytes: a path naming a device or a FIFO
// (session.json, a bodies or masks file, a calibration all come from the command line or a
// directory) read until it ended, and a FIFO's open waited for a writer.
TEST_F(JsonFileTest, OnlyRegularFilesWithinTheBoundAreRead) {
  const auto read = [](const std::string& path) { ReadJsonFile(path); };
  EXPECT_EQ(testing::ErrorOfReading(read, "/dev/zero"),
            "/dev/zero: not a regular file (a character device); a JSON file is a regular file of at most 16 MiB");
  const std::string fifo = testing::ErrorOfReadingAFifo(read, "session.json");
  EXPECT_NE(fifo.find("session.json: not a regular file (a FIFO)"), std::string::npos) << fifo;
  // Past the bound by a byte (a sparse file: its size is what is looked at first).
  const std::string large = Path("large.json");
  std::ofstream(large) << "[]";
  fs::resize_file(large, kMaxJsonFileBytes + 1);
  EXPECT_EQ(testing::ErrorOfReading(read, large), large + ": larger than 16 MiB, the bound for a JSON file");
  // At the bound it is read: "[]" and spaces.
  std::ofstream(large) << "[1]" << std::string(kMaxJsonFileBytes - 3, ' ');
  EXPECT_EQ(ReadJsonFile(large), nlohmann::json::array({1}));
}

}  // namespace
}  // namespace mocap

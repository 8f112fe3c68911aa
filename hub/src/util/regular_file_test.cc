// Whole-file reads with a bound: a regular file is read whole up to the bound and refused past it;
// /dev/zero, a FIFO and a directory are refused at once, naming the path and what it is.
#include "util/regular_file.h"

#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "util/special_file_testing.h"
#include "util/temporary_directory_testing.h"

namespace mocap {
namespace {

namespace fs = std::filesystem;

class RegularFileTest : public ::testing::Test {
 protected:
  std::string Write(const std::string& name, const std::string& bytes) const {
    const std::string path = dir_.File(name);
    std::ofstream(path, std::ios::binary) << bytes;
    return path;
  }
  static std::function<void(const std::string&)> Reader(size_t max_bytes) {
    return [max_bytes](const std::string& path) { ReadRegularFile(path, max_bytes, "a test file"); };
  }
  const testing::TemporaryDirectory dir_{"regular_file_test"};
};

TEST_F(RegularFileTest, ReadsAFileWholeUpToTheBound) {
  std::string bytes;
  for (int i = 0; i < 10000; ++i) bytes += static_cast<char>(i * 7 % 256);  // NULs and all
  const std::string path = Write("data", bytes);
  EXPECT_EQ(ReadRegularFile(path, bytes.size(), "a test file"), bytes);
  EXPECT_EQ(ReadRegularFile(path, 1 << 20, "a test file"), bytes);
  EXPECT_EQ(ReadRegularFile(Write("empty", ""), 0, "a test file"), "");
}

TEST_F(RegularFileTest, RefusesAFileOverTheBound) {
  const std::string path = Write("data", std::string(4097, 'x'));
  EXPECT_EQ(testing::ErrorOfReading(Reader(4096), path), path + ": larger than 4 KiB, the bound for a test file");
}

TEST_F(RegularFileTest, RefusesDevZeroAtOnce) {
  EXPECT_EQ(testing::ErrorOfReading(Reader(1 << 20), "/dev/zero"),
            "/dev/zero: not a regular file (a character device); a test file is a regular file of at most 1 MiB");
}

TEST_F(RegularFileTest, RefusesAFifoWithoutWaitingForAWriter) {
  const std::string error = testing::ErrorOfReadingAFifo(Reader(1 << 20), "pipe");
  EXPECT_NE(error.find("pipe: not a regular file (a FIFO)"), std::string::npos) << error;
}

TEST_F(RegularFileTest, RefusesADirectoryAndAMissingFile) {
  EXPECT_NE(testing::ErrorOfReading(Reader(100), dir_.path().string()).find(dir_.path().string() + ": not a regular file (a directory)"),
            std::string::npos);
  const std::string missing = dir_.File("missing");
  EXPECT_EQ(testing::ErrorOfReading(Reader(100), missing), missing + ": cannot open: No such file or directory");
}

TEST(ByteSizeText, NamesWholeUnits) {
  EXPECT_EQ(ByteSizeText(64 * 1024), "64 KiB");
  EXPECT_EQ(ByteSizeText(size_t{16} << 20), "16 MiB");
  EXPECT_EQ(ByteSizeText(size_t{4} << 30), "4 GiB");
  EXPECT_EQ(ByteSizeText(1536), "1536 bytes");
  EXPECT_EQ(ByteSizeText(0), "0 bytes");
}

}  // namespace
}  // namespace mocap

// An applied calibration keeps the file it replaces under a dated name, never over another kept
// one, and a replacement that cannot keep the old file writes nothing.
#include "service/calibration_files.h"

#include <filesystem>
#include <fstream>
#include <sstream>

#include <unistd.h>

#include <gtest/gtest.h>

#include "service/api_error.h"

namespace mocap::service {
namespace {

namespace fs = std::filesystem;

// 2026-11-27 23:07:04 UTC.
constexpr uint64_t kNowNs = 1'795'820'824'000'000'000ull;

std::string Read(const fs::path& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

class CalibrationFilesTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("calibration_files_test_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    path_ = (dir_ / "rig.json").string();
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
  std::string path_;
};

TEST_F(CalibrationFilesTest, DatedNameIsTheUtcTimeThenNumberedWhenTaken) {
  const std::string first = DatedCopyName(path_, kNowNs);
  EXPECT_EQ(first, path_ + ".2026-11-27T230704Z");
  std::ofstream(first) << "kept";
  EXPECT_EQ(DatedCopyName(path_, kNowNs), first + "-2");
  std::ofstream(first + "-2") << "kept too";
  EXPECT_EQ(DatedCopyName(path_, kNowNs), first + "-3");
}

TEST_F(CalibrationFilesTest, ReplacingKeepsTheOldFileBesideTheNew) {
  std::ofstream(path_) << "{\"old\": true}";
  ReplaceCalibrationKeepingOld(path_, nlohmann::json{{"new", true}}, kNowNs);
  EXPECT_EQ(nlohmann::json::parse(Read(path_)), (nlohmann::json{{"new", true}}));
  EXPECT_EQ(Read(path_ + ".2026-11-27T230704Z"), "{\"old\": true}");
  // A second apply in the same second keeps the first replacement too.
  ReplaceCalibrationKeepingOld(path_, nlohmann::json{{"newer", true}}, kNowNs);
  EXPECT_EQ(nlohmann::json::parse(Read(path_ + ".2026-11-27T230704Z-2")), (nlohmann::json{{"new", true}}));
  EXPECT_EQ(Read(path_ + ".2026-11-27T230704Z"), "{\"old\": true}");
}

TEST_F(CalibrationFilesTest, NoOldFileToKeepIsAServerErrorAndWritesNothing) {
  try {
    ReplaceCalibrationKeepingOld(path_, nlohmann::json{{"new", true}}, kNowNs);
    FAIL() << "replaced a calibration that does not exist";
  } catch (const ApiError& e) {
    EXPECT_EQ(e.status, 500);
    EXPECT_NE(std::string(e.what()).find("cannot keep the old calibration"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(path_));
}

}  // namespace
}  // namespace mocap::service

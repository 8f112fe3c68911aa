// The edit log of a recipe's results on a temporary directory: an empty log at first, a log that
// applies saved with the edited outputs beside the results (never over them), a refused log
// leaving everything as it was, undo as a shorter log.
#include "service/processed_edits.h"

#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "io/c3d.h"
#include "io/trajectory_file.h"
#include "service/api_error.h"

namespace mocap::service {
namespace {
namespace fs = std::filesystem;

fs::path Results() {
  const fs::path dir = fs::path(::testing::TempDir()) / "processed_edits" / "gait";
  fs::remove_all(dir);
  fs::create_directories(dir);
  MarkerTrajectories m;
  m.rate_hz = 100.0;
  m.names = {"A", "B"};
  for (size_t f = 0; f < 50; ++f) {
    const size_t i = m.AddFrame(f);
    m.At(i, 0) = Eigen::Vector3d(f * 2.0, 0, 1000);
    if (f < 20 || f > 29) m.At(i, 1) = Eigen::Vector3d(f * 3.0, 100, 1000);
  }
  WriteTrajectories(m, (dir / "markers.trc").string());
  WriteTrajectories(m, (dir / "markers.c3d").string());
  return dir;
}

nlohmann::json Log(const nlohmann::json& operations) {
  return {{"format", "mocap-edits"}, {"version", 1}, {"operations", operations}};
}

TEST(ProcessedEdits, AnAppliedLogIsSavedWithEditedOutputsBesideTheResults) {
  const fs::path dir = Results();
  const nlohmann::json first = ReadProcessedEdits(dir);
  EXPECT_TRUE(first["edits"]["operations"].empty());
  EXPECT_EQ(first["input"], "markers.trc");
  EXPECT_TRUE(first["outputs"].empty());
  const std::string before = [&] {
    std::ifstream in(dir / "markers.trc");
    return std::string(std::istreambuf_iterator<char>(in), {});
  }();

  const nlohmann::json fill = {{"op", "fill"}, {"marker", "B"}, {"method", "linear"}};
  const nlohmann::json answer = WriteProcessedEdits(dir, Log(nlohmann::json::array({fill})));
  EXPECT_EQ(answer["outputs"], nlohmann::json({"edited.trc", "edited.c3d", "edited.filled.tsv"}));
  ASSERT_EQ(answer["filled"].size(), 1u);
  EXPECT_EQ(answer["filled"][0]["first_frame"], 20);
  EXPECT_EQ(answer["filled"][0]["last_frame"], 29);
  EXPECT_EQ(answer["filled"][0]["method"], "linear");
  EXPECT_EQ(ReadProcessedEdits(dir)["edits"]["operations"].size(), 1u);
  std::vector<float> residuals;
  const MarkerTrajectories edited = ReadC3d((dir / "edited.c3d").string(), &residuals);
  EXPECT_NEAR(edited.At(25, 1).x(), 75.0, 1e-3);
  EXPECT_EQ(residuals[25 * 2 + 1], 0.0f);
  EXPECT_GT(residuals[15 * 2 + 1], 0.0f);
  std::ifstream in(dir / "markers.trc");
  EXPECT_EQ(std::string(std::istreambuf_iterator<char>(in), {}), before);  // the results are never written

  // Undo: the log without its last operation.
  const nlohmann::json undone = WriteProcessedEdits(dir, Log(nlohmann::json::array()));
  EXPECT_TRUE(undone["filled"].empty());
  EXPECT_FALSE(ReadTrajectories((dir / "edited.trc").string()).Has(25, 1));
}

TEST(ProcessedEdits, ARefusedLogChangesNothing) {
  const fs::path dir = Results();
  WriteProcessedEdits(dir, Log({{{"op", "rename"}, {"marker", "A"}, {"name", "LKNE"}}}));
  try {
    WriteProcessedEdits(dir, Log({{{"op", "delete"}, {"marker", "Z"}}}));
    FAIL() << "accepted";
  } catch (const ApiError& e) {
    EXPECT_EQ(e.status, 400);
    EXPECT_NE(std::string(e.what()).find("operation 1 (delete): marker 'Z' is not in the take"), std::string::npos) << e.what();
  }
  try {
    WriteProcessedEdits(dir, {{"format", "mocap-edits"}});
    FAIL() << "accepted";
  } catch (const ApiError& e) {
    EXPECT_EQ(e.status, 400);
  }
  EXPECT_EQ(ReadProcessedEdits(dir)["edits"]["operations"][0]["name"], "LKNE");
  EXPECT_EQ(ReadTrajectories((dir / "edited.trc").string()).names[0], "LKNE");
  fs::remove(dir / "markers.trc");
  fs::remove(dir / "markers.c3d");
  try {
    ReadProcessedEdits(dir);
    FAIL() << "no marker file, yet answered";
  } catch (const ApiError& e) {
    EXPECT_EQ(e.status, 404);
  }
}

}  // namespace
}  // namespace mocap::service

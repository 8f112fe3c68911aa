// The spill file becomes a TRC with one column per marker, gaps as empty cells, and is removed.
#include "track/trc_spill.h"

#include <filesystem>

#include <gtest/gtest.h>

#include "io/trc.h"

namespace mocap {
namespace {

TEST(TrcSpill, WritesRowsAsTrcAndRemovesSpill) {
  const std::string path = (std::filesystem::temp_directory_path() / "trc_spill_test.trc").string();
  {
    TrcSpill spill;
    spill.Open(path, 100.0);
    TrackSample a;
    a.marker = 0;
    a.position = Eigen::Vector3d(1, 2, 3);
    TrackSample b;
    b.marker = 2;
    b.position = Eigen::Vector3d(-4, 5.5, 6);
    spill.AddRow(10, {a, b});
    spill.AddRow(11, {});
    a.position.x() = 7;
    spill.AddRow(12, {a});
    EXPECT_TRUE(std::filesystem::exists(path + ".spill"));
    spill.Finish(3);
    EXPECT_EQ(spill.rows(), 3u);
  }
  EXPECT_FALSE(std::filesystem::exists(path + ".spill"));
  const MarkerTrajectories trc = ReadTrc(path);
  ASSERT_EQ(trc.NumMarkers(), 3u);
  ASSERT_EQ(trc.NumFrames(), 3u);
  EXPECT_EQ(trc.names[0], "M001");
  EXPECT_EQ(trc.frame_numbers[0], 10u);
  EXPECT_LT((trc.At(0, 0) - Eigen::Vector3d(1, 2, 3)).norm(), 1e-4);
  EXPECT_LT((trc.At(0, 2) - Eigen::Vector3d(-4, 5.5, 6)).norm(), 1e-4);
  EXPECT_FALSE(trc.Has(0, 1));
  EXPECT_FALSE(trc.Has(1, 0));
  EXPECT_LT((trc.At(2, 0) - Eigen::Vector3d(7, 2, 3)).norm(), 1e-4);
  std::filesystem::remove(path);
}

TEST(TrcSpill, NothingTrackedIsAnError) {
  const std::string path = (std::filesystem::temp_directory_path() / "trc_spill_empty.trc").string();
  TrcSpill spill;
  spill.Open(path, 100.0);
  spill.AddRow(0, {});
  EXPECT_THROW(spill.Finish(0), std::runtime_error);
}

}  // namespace
}  // namespace mocap

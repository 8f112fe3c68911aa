// Live wand coverage: which camera frames count as wand samples, where their sightings land in
// the grid, and the advice that names the emptiest region of the image.
#include "calib/wand_coverage.h"

#include <stdexcept>

#include <gtest/gtest.h>

#include "simcore/test_scenes.h"

namespace mocap {
namespace {

Rig TwoCameras() {
  Rig rig;
  for (uint32_t id : {4u, 7u}) {
    Camera c;
    c.id = id;
    c.intrinsics.width = 800;
    c.intrinsics.height = 600;
    rig.cameras.push_back(c);
  }
  return rig;
}

CameraFrame View(uint32_t camera, std::vector<Eigen::Vector2d> pixels) {
  CameraFrame f;
  f.camera_id = camera;
  for (const auto& p : pixels) {
    Blob b;
    b.pixel = p;
    b.area = 20;
    f.blobs.push_back(b);
  }
  return f;
}

FrameSet Set(std::vector<CameraFrame> views) {
  FrameSet s;
  s.cameras = std::move(views);
  return s;
}

TEST(WandCoverage, CountsOnlyFramesWithTheWandAloneInTwoCameras) {
  WandCoverageOptions o;
  o.columns = 4;
  o.rows = 3;
  o.cell_samples = 1;
  WandCoverage coverage(TwoCameras(), 2, o);
  // Both see exactly two well separated blobs: a sample for each.
  EXPECT_TRUE(coverage.Add(Set({View(4, {{10, 10}, {790, 590}}), View(7, {{400, 300}, {450, 300}})})));
  // Camera 7 sees three blobs (a reflection): no other camera sees the wand alone, so nothing counts.
  EXPECT_FALSE(coverage.Add(Set({View(4, {{10, 10}, {100, 10}}), View(7, {{1, 1}, {50, 50}, {90, 90}})})));
  // Blobs closer than the separation limit, and a blob outside the image, are not the wand.
  EXPECT_FALSE(coverage.Add(Set({View(4, {{10, 10}, {12, 11}}), View(7, {{400, 300}, {450, 300}})})));
  EXPECT_FALSE(coverage.Add(Set({View(4, {{10, 10}, {900, 11}}), View(7, {{400, 300}, {450, 300}})})));
  // A camera not in the rig is ignored.
  EXPECT_FALSE(coverage.Add(Set({View(9, {{10, 10}, {100, 10}}), View(7, {{400, 300}, {450, 300}})})));
  EXPECT_EQ(coverage.frame_sets(), 5u);
  EXPECT_EQ(coverage.wand_frames(), 1u);
  const CameraCoverage& c4 = coverage.cameras()[0];
  EXPECT_EQ(c4.id, 4u);
  EXPECT_EQ(c4.samples, 1u);
  ASSERT_EQ(c4.counts.size(), 12u);
  EXPECT_EQ(c4.counts[0], 1u);                 // top left cell
  EXPECT_EQ(c4.counts[2 * 4 + 3], 1u);         // bottom right cell
  EXPECT_DOUBLE_EQ(c4.Share(1), 2.0 / 12.0);
  const CameraCoverage& c7 = coverage.cameras()[1];
  EXPECT_EQ(c7.counts[1 * 4 + 2], 2u);         // both markers in the cell right of the centre
  EXPECT_DOUBLE_EQ(c7.Share(2), 1.0 / 12.0);
  EXPECT_DOUBLE_EQ(c7.Share(3), 0.0);
}

TEST(WandCoverage, AdviceNamesTheEmptiestRegionUntilTheTargetsAreMet) {
  WandCoverageOptions o;
  o.columns = 6;
  o.rows = 6;
  o.cell_samples = 1;
  WandCoverage coverage(TwoCameras(), 2, o);
  EXPECT_FALSE(coverage.Advise(0, 1, 0.5).enough);
  EXPECT_NE(coverage.Advise(0, 1, 0.5).text.find("has not seen the wand"), std::string::npos);
  // Fill every cell of camera 4 but those of the top left ninth (columns 0-1, rows 0-1).
  for (int row = 0; row < 6; ++row) {
    for (int column = 0; column < 6; ++column) {
      if (row < 2 && column < 2) continue;
      const Eigen::Vector2d p(column * 800.0 / 6 + 60, row * 600.0 / 6 + 50);
      coverage.Add(Set({View(4, {p, p + Eigen::Vector2d(30, 0)}), View(7, {{400, 300}, {450, 300}})}));
    }
  }
  const CoverageAdvice a = coverage.Advise(0, 10, 0.95);
  EXPECT_FALSE(a.enough);
  EXPECT_EQ(a.region, "top left");
  EXPECT_EQ(a.text.rfind("camera 4: wave towards the top left", 0), 0u) << a.text;
  // 32 of 36 cells are covered: enough for a target of 0.8 with 32 samples.
  EXPECT_TRUE(coverage.Advise(0, 32, 0.8).enough);
  EXPECT_FALSE(coverage.Advise(0, 33, 0.8).enough);
  EXPECT_NE(coverage.Advise(0, 33, 0.8).text.find("keep waving"), std::string::npos);
  // Camera 7 saw the wand only right of the centre.
  EXPECT_EQ(coverage.Advise(1, 1, 0.5).region, "top left");
}

TEST(WandCoverage, RegionNamesAndOptionChecks) {
  EXPECT_EQ(ImageRegionName(0, 0, 9, 9), "top left");
  EXPECT_EQ(ImageRegionName(4, 0, 9, 9), "top");
  EXPECT_EQ(ImageRegionName(8, 4, 9, 9), "right");
  EXPECT_EQ(ImageRegionName(4, 4, 9, 9), "centre");
  EXPECT_EQ(ImageRegionName(8, 8, 9, 9), "bottom right");
  WandCoverageOptions o;
  o.columns = 0;
  EXPECT_THROW(o.Check(), std::invalid_argument);
  o = WandCoverageOptions();
  o.cell_samples = 0;
  EXPECT_THROW(o.Check(), std::invalid_argument);
  EXPECT_THROW(WandCoverage(TwoCameras(), 4, WandCoverageOptions()), std::invalid_argument);
}

TEST(WandCoverage, ASimulatedWaveCoversEveryCamera) {
  const Rig rig = testing::RingRig(6, 5);
  const testing::WandScene scene = testing::MakeWandScene(rig, {-250.0, 250.0}, 1500, 0.1, 6);
  WandCoverage coverage(rig, 2, WandCoverageOptions());
  size_t counted = 0;
  for (const FrameSet& set : scene.frames) counted += coverage.Add(set);
  EXPECT_GT(counted, 500u);
  for (size_t i = 0; i < coverage.cameras().size(); ++i) {
    EXPECT_GT(coverage.cameras()[i].samples, 200u) << i;
    EXPECT_GT(coverage.cameras()[i].Share(4), 0.3) << i;
  }
}

}  // namespace
}  // namespace mocap

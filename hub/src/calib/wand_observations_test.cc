// Wand frame selection: static reflections are masked so the wand's views survive, extra or
// missing blobs and merged blobs disqualify a view, three-marker views are ordered along the
// wand and non-collinear triples are refused.
#include "calib/wand_observations.h"

#include <stdexcept>

#include <gtest/gtest.h>

#include "simcore/test_scenes.h"

namespace mocap {
namespace {

TEST(WandObservationsTest, StaticReflectionsAreMaskedAndFlickerDisqualifies) {
  const Rig rig = testing::RingRig(4, 1);
  const WandGeometry wand = WandGeometry::TwoMarker(500.0);
  testing::WandScene scene = testing::MakeWandScene(rig, wand.marker_offsets_mm, 300, 0.1, 2);
  WandSelectionStats clean;
  const size_t clean_frames = SelectWandFrames(scene.frames, rig, wand, WandSelectionOptions(), &clean).size();
  ASSERT_GT(clean_frames, 100u);
  for (FrameSet& set : scene.frames) {
    // Camera 1 sees a lamp reflection in every frame; camera 2 a flicker in every tenth frame.
    Blob lamp;
    lamp.pixel = Eigen::Vector2d(100.3, 700.8);
    set.cameras[0].blobs.push_back(lamp);
    if (set.frame_number % 10 == 0) {
      Blob flicker;
      flicker.pixel = Eigen::Vector2d(20.0 + set.frame_number, 30.0);
      set.cameras[1].blobs.push_back(flicker);
    }
  }
  WandSelectionStats stats;
  SelectWandFrames(scene.frames, rig, wand, WandSelectionOptions(), &stats);
  EXPECT_EQ(stats.static_blobs_masked[0], 300u);
  EXPECT_EQ(stats.views_selected[0], clean.views_selected[0]);
  EXPECT_LT(stats.views_selected[1], clean.views_selected[1]);
  EXPECT_GT(stats.views_selected[1], clean.views_selected[1] * 8 / 10);
}

TEST(WandObservationsTest, MergedAndCrowdedViewsAreSkipped) {
  Rig rig;
  rig.cameras.push_back(testing::LookAtCamera(1, Eigen::Vector3d(0, -3000, 1000), Eigen::Vector3d(0, 0, 1000)));
  rig.cameras.push_back(testing::LookAtCamera(2, Eigen::Vector3d(3000, 0, 1000), Eigen::Vector3d(0, 0, 1000)));
  const WandGeometry wand = WandGeometry::TwoMarker(500.0);
  FrameSet set;
  for (uint32_t id : {1u, 2u}) {
    CameraFrame frame;
    frame.camera_id = id;
    Blob a, b;
    a.pixel = Eigen::Vector2d(300, 400);
    b.pixel = Eigen::Vector2d(700, 420);
    frame.blobs = {a, b};
    set.cameras.push_back(frame);
  }
  EXPECT_EQ(SelectWandFrames({set}, rig, wand, WandSelectionOptions(), nullptr).size(), 1u);
  FrameSet merged = set;
  merged.cameras[1].blobs[0].flags = kBlobMerged;
  EXPECT_TRUE(SelectWandFrames({merged}, rig, wand, WandSelectionOptions(), nullptr).empty());
  FrameSet crowded = set;
  crowded.cameras[0].blobs[1].pixel = Eigen::Vector2d(303, 401);
  EXPECT_TRUE(SelectWandFrames({crowded}, rig, wand, WandSelectionOptions(), nullptr).empty());
}

TEST(WandObservationsTest, ThreeMarkerViewsAreOrderedAlongTheWand) {
  Rig rig;
  rig.cameras.push_back(testing::LookAtCamera(1, Eigen::Vector3d(0, -3000, 1000), Eigen::Vector3d(0, 0, 1000)));
  rig.cameras.push_back(testing::LookAtCamera(2, Eigen::Vector3d(3000, 0, 1000), Eigen::Vector3d(0, 0, 1000)));
  const WandGeometry wand = WandGeometry::ThreeMarker(500.0, 150.0);
  FrameSet set;
  for (uint32_t id : {1u, 2u}) {
    CameraFrame frame;
    frame.camera_id = id;
    Blob end_a, middle, end_b;
    end_a.pixel = Eigen::Vector2d(300, 400);
    middle.pixel = Eigen::Vector2d(420, 406);
    end_b.pixel = Eigen::Vector2d(700, 420);
    frame.blobs = {middle, end_b, end_a};
    set.cameras.push_back(frame);
  }
  const auto frames = SelectWandFrames({set}, rig, wand, WandSelectionOptions(), nullptr);
  ASSERT_EQ(frames.size(), 1u);
  EXPECT_EQ(frames[0].views[0].pixels[1], Eigen::Vector2d(420, 406));
  // A middle blob far off the line between the ends is not the wand.
  set.cameras[0].blobs[0].pixel = Eigen::Vector2d(420, 520);
  EXPECT_TRUE(SelectWandFrames({set}, rig, wand, WandSelectionOptions(), nullptr).empty());
  EXPECT_THROW(WandGeometry::ThreeMarker(500.0, 250.0).Check(), std::invalid_argument);
}

}  // namespace
}  // namespace mocap

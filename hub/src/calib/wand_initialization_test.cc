// Initial poses from essential matrices on a noisy synthetic ring: every camera is placed
// relative to the reference camera with metric scale from the wand length; too little shared
// data is refused with a reason.
#include "calib/wand_initialization.h"

#include <cmath>
#include <stdexcept>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "simcore/test_scenes.h"
#include "calib/wand_observations.h"

namespace mocap {
namespace {

double AngleDeg(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b) {
  return Eigen::AngleAxisd(a * b.transpose()).angle() * 180.0 / M_PI;
}

struct Scene {
  Rig truth = testing::RingRig(6, 3);
  WandGeometry wand = WandGeometry::TwoMarker(500.0);
  std::vector<WandFrame> frames;

  explicit Scene(int num_frames) {
    const testing::WandScene scene = testing::MakeWandScene(truth, wand.marker_offsets_mm, num_frames, 0.15, 5);
    WandSelectionStats stats;
    frames = SelectWandFrames(scene.frames, truth, wand, WandSelectionOptions(), &stats);
  }
};

TEST(WandInitialization, RecoversRelativePosesWithMetricScale) {
  const Scene scene(800);
  WandInitializationOptions options;
  const WandInitialization init = InitializeWandPoses(scene.frames, scene.truth, scene.wand, options);
  ASSERT_EQ(init.cameras.size(), scene.truth.cameras.size());
  const Camera& reference = scene.truth.cameras[init.reference_camera];
  EXPECT_TRUE(init.cameras[init.reference_camera].rotation.isIdentity(1e-12));
  EXPECT_TRUE(init.cameras[init.reference_camera].translation.isZero(1e-12));
  for (size_t i = 0; i < init.cameras.size(); ++i) {
    ASSERT_TRUE(init.posed[i]) << "camera " << i << ": " << init.unposed_reason[i];
    if (i == init.reference_camera) continue;
    // Truth in the reference camera's frame: cam_i_from_reference.
    const Eigen::Matrix3d rotation = scene.truth.cameras[i].rotation * reference.rotation.transpose();
    const Eigen::Vector3d translation = scene.truth.cameras[i].translation - rotation * reference.translation;
    // A start for the bundle adjustment, not its result: chained pairs on 0.15 px noise measure
    // up to 0.65 degrees and 1.2 % of the baseline (4-7 m; the scale comes from 500 mm wand
    // lengths). The limits leave room for that and fail on a wrong pose or scale.
    EXPECT_LT(AngleDeg(init.cameras[i].rotation, rotation), 1.0) << "camera " << i;
    EXPECT_LT((init.cameras[i].translation - translation).norm(), 0.02 * translation.norm()) << "camera " << i;
  }
}

TEST(WandInitialization, RefusesTooFewSharedFrames) {
  const Scene scene(12);
  EXPECT_THROW(InitializeWandPoses(scene.frames, scene.truth, scene.wand, WandInitializationOptions()),
               std::runtime_error);

  std::vector<std::pair<const WandView*, const WandView*>> pairs;
  for (const WandFrame& frame : scene.frames) {
    if (frame.views.size() >= 2) pairs.emplace_back(&frame.views[0], &frame.views[1]);
  }
  RelativePose pose;
  std::string why;
  EXPECT_FALSE(EstimateWandRelativePose(pairs, scene.wand, 900.0, WandInitializationOptions(), &pose, &why));
  EXPECT_NE(why.find("shared wand frames"), std::string::npos) << why;
}

TEST(WandInitialization, OptionsAreChecked) {
  WandInitializationOptions options;
  options.min_pair_frames = 4;
  EXPECT_THROW(options.Check(), std::invalid_argument);
}

}  // namespace
}  // namespace mocap

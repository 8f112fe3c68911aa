// World frame: an L-frame seen by a rig whose world is elsewhere (as after a wand calibration)
// moves the world back onto the L-frame; model matching copes with order and extra points and
// refuses symmetric models; floor levelling makes the floor plane up = 0.
#include "calib/world_frame.h"

#include <algorithm>
#include <random>
#include <stdexcept>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "simcore/test_scenes.h"

namespace mocap {
namespace {

// The rig as a calibration with another world frame would describe it.
Rig MovedWorld(const Rig& rig) {
  SimilarityTransform moved;
  moved.rotation = Eigen::AngleAxisd(1.3, Eigen::Vector3d(0.3, -0.4, 0.8).normalized()).toRotationMatrix();
  moved.translation = Eigen::Vector3d(-2500.0, 700.0, 4100.0);
  return TransformRig(rig, moved);
}

std::vector<FrameSet> ProjectStatic(const Rig& rig, const std::vector<Eigen::Vector3d>& points, int frames,
                                    double noise_px, uint32_t seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, noise_px);
  std::vector<FrameSet> sets;
  for (int f = 0; f < frames; ++f) {
    FrameSet set;
    set.frame_number = static_cast<uint64_t>(f);
    for (const Camera& camera : rig.cameras) {
      CameraFrame frame;
      frame.camera_id = camera.id;
      frame.frame_number = set.frame_number;
      for (const Eigen::Vector3d& point : points) {
        Eigen::Vector2d pixel;
        if (!camera.ProjectToPixel(point, &pixel) || !camera.InImage(pixel)) continue;
        Blob blob;
        blob.pixel = pixel + Eigen::Vector2d(noise(rng), noise(rng));
        frame.blobs.push_back(blob);
      }
      set.cameras.push_back(frame);
    }
    sets.push_back(set);
  }
  return sets;
}

TEST(WorldFrameTest, LFrameBringsTheWorldBack) {
  const Rig truth = testing::RingRig(8, 3);
  const Rig calibrated = MovedWorld(truth);
  const std::vector<Eigen::Vector3d> model = DefaultLFrame(2);
  std::vector<Eigen::Vector3d> scene = model;
  scene.emplace_back(900.0, -600.0, 1200.0);  // a stray marker elsewhere in the volume
  // One second of a static L-frame at 100 Hz: its small size makes averaging over frames matter.
  const std::vector<FrameSet> frames = ProjectStatic(truth, scene, 100, 0.15, 4);
  const WorldFrameFit fit = LocateLFrame(frames, calibrated, model, LFrameOptions());
  EXPECT_EQ(fit.frames_used, 100);
  EXPECT_LT(fit.fit_rms_mm, 0.5);
  const Rig result = TransformRig(calibrated, fit.new_from_old);
  for (size_t i = 0; i < truth.cameras.size(); ++i) {
    EXPECT_LT((result.cameras[i].CenterInWorld() - truth.cameras[i].CenterInWorld()).norm(), 3.0);
    const double angle = Eigen::AngleAxisd(result.cameras[i].rotation * truth.cameras[i].rotation.transpose()).angle();
    EXPECT_LT(angle * 180.0 / M_PI, 0.1);
  }
}

TEST(WorldFrameTest, MissingLFrameIsReportedWithAdvice) {
  const Rig truth = testing::RingRig(6, 5);
  const std::vector<FrameSet> frames = ProjectStatic(truth, {{0, 0, 0}, {200, 0, 0}}, 10, 0.1, 6);
  try {
    LocateLFrame(frames, truth, DefaultLFrame(2), LFrameOptions());
    FAIL() << "expected a refusal";
  } catch (const std::runtime_error& error) {
    EXPECT_NE(std::string(error.what()).find("found in 0 frames"), std::string::npos) << error.what();
  }
}

TEST(MatchModelTest, FindsTheModelAmongShuffledAndExtraPoints) {
  const std::vector<Eigen::Vector3d> model = DefaultLFrame(1);
  const Eigen::Matrix3d rotation = Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitY()).toRotationMatrix();
  std::vector<Eigen::Vector3d> points;
  for (const auto& m : model) points.push_back(rotation * m + Eigen::Vector3d(100, 0, 50));
  points.emplace_back(300.0, 0.0, 300.0);
  points.emplace_back(-400.0, 10.0, 20.0);
  std::vector<Eigen::Vector3d> truth_order = points;
  std::mt19937 rng(7);
  std::shuffle(points.begin(), points.end(), rng);
  std::vector<Eigen::Vector3d> matched;
  ASSERT_TRUE(MatchModel(points, model, 2.0, &matched));
  for (size_t k = 0; k < model.size(); ++k) EXPECT_LT((matched[k] - truth_order[k]).norm(), 1e-9);
  // Distorted beyond the tolerance: no match.
  points = truth_order;
  points[1] += Eigen::Vector3d(0.0, 30.0, 0.0);
  EXPECT_FALSE(MatchModel({points[0], points[1], points[2], points[3]}, model, 2.0, &matched));
}

TEST(WorldFrameTest, SymmetricModelIsRefused) {
  const Rig truth = testing::RingRig(4, 8);
  const std::vector<Eigen::Vector3d> square = {{0, 0, 0}, {300, 0, 0}, {300, 300, 0}, {0, 300, 0}};
  EXPECT_THROW(LocateLFrame({}, truth, square, LFrameOptions()), std::invalid_argument);
  const std::vector<Eigen::Vector3d> line = {{0, 0, 0}, {100, 0, 0}, {400, 0, 0}};
  EXPECT_THROW(LocateLFrame({}, truth, line, LFrameOptions()), std::invalid_argument);
}

TEST(WorldFrameTest, FloorPointsLevelTheWorld) {
  const Rig truth = testing::RingRig(6, 9);
  const Rig calibrated = MovedWorld(truth);
  const SimilarityTransform to_calibrated = [&] {
    SimilarityTransform t;
    t.rotation = calibrated.cameras[0].rotation.transpose() * truth.cameras[0].rotation;
    t.translation = calibrated.cameras[0].CenterInWorld() - t.rotation * truth.cameras[0].CenterInWorld();
    return t;
  }();
  std::vector<Eigen::Vector3d> floor;
  for (const Eigen::Vector3d& p : {Eigen::Vector3d(-800, -500, 0), Eigen::Vector3d(900, -300, 0),
                                  Eigen::Vector3d(100, 1000, 0), Eigen::Vector3d(-200, 200, 0)}) {
    floor.push_back(to_calibrated.Apply(p));
  }
  const WorldFrameFit fit = LevelOnFloor(floor, calibrated, 2);
  EXPECT_LT(fit.fit_rms_mm, 1e-6);
  const Rig result = TransformRig(calibrated, fit.new_from_old);
  for (size_t i = 0; i < truth.cameras.size(); ++i) {
    EXPECT_NEAR(result.cameras[i].CenterInWorld().z(), truth.cameras[i].CenterInWorld().z(), 1e-6);
  }
  EXPECT_THROW(LevelOnFloor({{0, 0, 0}, {1, 0, 0}, {2, 0, 0}}, calibrated, 2), std::invalid_argument);
}

}  // namespace
}  // namespace mocap

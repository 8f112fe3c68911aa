// Bundle adjustment from perturbed cameras and wand poses on noisy synthetic ground truth: the
// reprojection error falls to the noise level and poses and scale come back; inconsistent input
// is refused.
#include "calib/wand_bundle_adjustment.h"

#include <cmath>
#include <random>
#include <stdexcept>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "simcore/test_scenes.h"

namespace mocap {
namespace {

constexpr double kNoisePx = 0.2;

struct Scene {
  Rig truth = testing::RingRig(6, 11);
  WandGeometry wand = WandGeometry::TwoMarker(500.0);
  std::vector<WandFrame> frames;
  std::vector<WandPose> poses;  // truth, one per frame
};

// Labelled wand views (ends in marker order) of random wand poses, with Gaussian pixel noise.
Scene MakeScene(int num_frames) {
  Scene scene;
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> box(-1.0, 1.0);
  std::normal_distribution<double> noise(0.0, kNoisePx);
  while (static_cast<int>(scene.frames.size()) < num_frames) {
    WandPose pose;
    pose.centre = Eigen::Vector3d(1500.0 * box(rng), 1500.0 * box(rng), 1000.0 + 700.0 * box(rng));
    pose.axis = Eigen::Vector3d(box(rng), box(rng), box(rng)).normalized();
    WandFrame frame;
    frame.frame_number = scene.frames.size();
    for (size_t c = 0; c < scene.truth.cameras.size(); ++c) {
      const Camera& camera = scene.truth.cameras[c];
      WandView view;
      view.camera = c;
      for (size_t k = 0; k < scene.wand.MarkerCount(); ++k) {
        Eigen::Vector2d pixel;
        if (!camera.ProjectToPixel(pose.Marker(scene.wand, k), &pixel) || !camera.InImage(pixel)) break;
        pixel += Eigen::Vector2d(noise(rng), noise(rng));
        view.pixels.push_back(pixel);
        view.normalized.push_back(camera.UndistortPixel(pixel));
      }
      if (view.pixels.size() == scene.wand.MarkerCount()) frame.views.push_back(view);
    }
    if (frame.views.size() < 2) continue;
    scene.frames.push_back(frame);
    scene.poses.push_back(pose);
  }
  return scene;
}

double RmsPx(const Scene& scene, const std::vector<Camera>& cameras, const std::vector<WandPose>& poses) {
  double sum = 0.0;
  size_t count = 0;
  for (size_t f = 0; f < scene.frames.size(); ++f) {
    for (const WandView& view : scene.frames[f].views) {
      for (size_t k = 0; k < view.pixels.size(); ++k) {
        Eigen::Vector2d projected;
        if (!cameras[view.camera].ProjectToPixel(poses[f].Marker(scene.wand, k), &projected)) continue;
        sum += (projected - view.pixels[k]).squaredNorm();
        ++count;
      }
    }
  }
  return std::sqrt(sum / static_cast<double>(count));
}

TEST(WandBundleAdjustment, RecoversPosesAndScaleFromPerturbedStart) {
  const Scene scene = MakeScene(400);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  // Camera 0 stays at truth (it fixes the gauge); the others start 1 degree and 50 mm off, the
  // wand poses 30 mm and a few degrees off: a start the initialisation easily reaches.
  std::vector<Camera> cameras = scene.truth.cameras;
  for (size_t i = 1; i < cameras.size(); ++i) {
    const Eigen::Vector3d axis = Eigen::Vector3d(unit(rng), unit(rng), unit(rng)).normalized();
    cameras[i].rotation = Eigen::AngleAxisd(M_PI / 180.0, axis).toRotationMatrix() * cameras[i].rotation;
    cameras[i].translation += 50.0 * Eigen::Vector3d(unit(rng), unit(rng), unit(rng)).normalized();
  }
  std::vector<WandPose> poses = scene.poses;
  for (WandPose& pose : poses) {
    pose.centre += 30.0 * Eigen::Vector3d(unit(rng), unit(rng), unit(rng)).normalized();
    pose.axis = (pose.axis + 0.05 * Eigen::Vector3d(unit(rng), unit(rng), unit(rng))).normalized();
  }
  const double rms_before = RmsPx(scene, cameras, poses);

  WandBundleOptions options;
  options.fixed_camera = 0;
  const std::vector<bool> active(cameras.size(), true);
  const WandBundleSummary summary = AdjustWandBundle(scene.frames, scene.wand, options, active, &cameras, &poses);
  ASSERT_TRUE(summary.usable) << summary.message;
  EXPECT_LT(summary.final_cost, summary.initial_cost);
  const double rms_after = RmsPx(scene, cameras, poses);
  EXPECT_GT(rms_before, 5.0);
  // Noise sigma is per coordinate; the error length of an observation has RMS sqrt(2) sigma.
  EXPECT_LT(rms_after, 1.2 * std::sqrt(2.0) * kNoisePx);
  // Camera 0 fixes position and orientation; the wand length alone fixes the scale, so every
  // centre coming back to truth shows the scale is recovered as well.
  for (size_t i = 0; i < cameras.size(); ++i) {
    const Camera& truth = scene.truth.cameras[i];
    EXPECT_LT((cameras[i].CenterInWorld() - truth.CenterInWorld()).norm(), 2.0) << "camera " << i;
    EXPECT_LT(Eigen::AngleAxisd(cameras[i].rotation * truth.rotation.transpose()).angle() * 180.0 / M_PI, 0.02)
        << "camera " << i;
  }
  for (size_t f = 0; f < poses.size(); ++f) {
    EXPECT_LT((poses[f].centre - scene.poses[f].centre).norm(), 2.0) << "frame " << f;
  }
}

TEST(WandBundleAdjustment, RefusesInconsistentInput) {
  Scene scene = MakeScene(20);
  std::vector<Camera> cameras = scene.truth.cameras;
  std::vector<WandPose> poses = scene.poses;
  WandBundleOptions options;
  std::vector<bool> active(cameras.size(), true);
  // One wand pose short of the frames.
  poses.pop_back();
  EXPECT_THROW(AdjustWandBundle(scene.frames, scene.wand, options, active, &cameras, &poses),
               std::invalid_argument);
  poses = scene.poses;
  // The camera that fixes the gauge is not being solved.
  active[options.fixed_camera] = false;
  EXPECT_THROW(AdjustWandBundle(scene.frames, scene.wand, options, active, &cameras, &poses),
               std::invalid_argument);
  active[options.fixed_camera] = true;
  options.max_iterations = 0;
  EXPECT_THROW(AdjustWandBundle(scene.frames, scene.wand, options, active, &cameras, &poses),
               std::invalid_argument);
}

}  // namespace
}  // namespace mocap

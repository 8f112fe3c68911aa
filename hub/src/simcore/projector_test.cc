// Tests of the fault model: exact projections without faults, and each fault's statistics.
#include "simcore/projector.h"

#include <cmath>
#include <map>
#include <stdexcept>

#include <gtest/gtest.h>

#include "io/marker_trajectories.h"
#include "simcore/ring_rig.h"
#include "simcore/synthetic_motion.h"

namespace mocap {
namespace {

struct Scene {
  MarkerTrajectories motion;
  Rig rig;
};

Scene MakeScene(int frames = 60, int markers = 20) {
  SyntheticMotionOptions motion_options;
  motion_options.frames = frames;
  motion_options.markers = markers;
  Scene scene;
  scene.motion = MakeSyntheticMotion(motion_options);
  // The rig frames a full 20-marker body (the same seed places the first markers identically).
  motion_options.markers = 20;
  RingRigOptions rig_options;
  rig_options.cameras = 4;
  scene.rig = MakeRingRig(ComputeMotionVolume(MakeSyntheticMotion(motion_options), 2), rig_options);
  return scene;
}

// Closest blob to a pixel (distance returned through *distance).
const Blob* Nearest(const CameraFrame& frame, const Eigen::Vector2d& pixel, double* distance) {
  const Blob* best = nullptr;
  *distance = 1e300;
  for (const Blob& blob : frame.blobs) {
    const double d = (blob.pixel - pixel).norm();
    if (d < *distance) {
      *distance = d;
      best = &blob;
    }
  }
  return best;
}

TEST(ProjectorTest, WithoutFaultsBlobsAreTheProjections) {
  const Scene scene = MakeScene();
  ProjectOptions options;
  options.merge_px = 0.0;  // the synthetic markers are apart, but keep every blob separate
  FaultyProjector projector(scene.rig, scene.motion.NumMarkers(), options);
  std::vector<int> seeing;
  for (size_t f = 0; f < scene.motion.NumFrames(); ++f) {
    const std::vector<CameraFrame> frames =
        projector.Project(scene.motion.frame_numbers[f], 1000 + f, &scene.motion.points[f * 20], &seeing);
    ASSERT_EQ(frames.size(), 4u);
    for (int count : seeing) EXPECT_EQ(count, 4);
    for (size_t c = 0; c < 4; ++c) {
      const Camera& camera = scene.rig.cameras[c];
      const CameraFrame& frame = frames[c];
      EXPECT_EQ(frame.camera_id, camera.id);
      EXPECT_EQ(frame.frame_number, scene.motion.frame_numbers[f]);
      EXPECT_EQ(frame.trigger_time_ns, 1000 + f);
      EXPECT_EQ(frame.width, 1280u);
      ASSERT_EQ(frame.blobs.size(), 20u);
      for (size_t m = 0; m < 20; ++m) {
        Eigen::Vector2d pixel;
        ASSERT_TRUE(camera.ProjectToPixel(scene.motion.At(f, m), &pixel));
        double distance = 0.0;
        Nearest(frame, pixel, &distance);
        EXPECT_LT(distance, 1e-9);
      }
      for (size_t b = 1; b < frame.blobs.size(); ++b) {
        EXPECT_LE(frame.blobs[b - 1].pixel.y(), frame.blobs[b].pixel.y()) << "scanline order";
      }
    }
  }
}

TEST(ProjectorTest, NoiseHasTheRequestedSigma) {
  const Scene scene = MakeScene(40);
  ProjectOptions options;
  options.merge_px = 0.0;
  options.noise_px = 0.3;
  FaultyProjector projector(scene.rig, 20, options);
  std::vector<int> seeing;
  double sum_squares = 0.0;
  int samples = 0;
  for (size_t f = 0; f < scene.motion.NumFrames(); ++f) {
    const auto frames = projector.Project(f, 0, &scene.motion.points[f * 20], &seeing);
    for (size_t c = 0; c < frames.size(); ++c) {
      for (size_t m = 0; m < 20; ++m) {
        Eigen::Vector2d pixel;
        ASSERT_TRUE(scene.rig.cameras[c].ProjectToPixel(scene.motion.At(f, m), &pixel));
        double distance = 0.0;
        Nearest(frames[c], pixel, &distance);
        sum_squares += distance * distance;
        ++samples;
      }
    }
  }
  // Two axes: E[d^2] = 2 sigma^2.
  EXPECT_NEAR(std::sqrt(sum_squares / samples / 2.0), 0.3, 0.02);
}

TEST(ProjectorTest, OcclusionRateAndDuration) {
  const Scene scene = MakeScene(2000, 10);
  ProjectOptions options;
  options.merge_px = 0.0;
  options.occlusion = 0.1;
  options.occlusion_frames = 8.0;
  FaultyProjector projector(scene.rig, 10, options);
  std::vector<int> seeing;
  // Occlusion runs of each marker as camera 0 sees them.
  std::vector<int> run(10, 0);
  int hidden = 0, total = 0, runs = 0, run_frames = 0;
  for (size_t f = 0; f < scene.motion.NumFrames(); ++f) {
    const auto frames = projector.Project(f, 0, &scene.motion.points[f * 10], &seeing);
    ASSERT_EQ(frames.size(), 4u);
    for (size_t m = 0; m < 10; ++m) {
      Eigen::Vector2d pixel;
      ASSERT_TRUE(scene.rig.cameras[0].ProjectToPixel(scene.motion.At(f, m), &pixel));
      double distance = 0.0;
      Nearest(frames[0], pixel, &distance);
      const bool is_hidden = distance > 1e-6;
      hidden += is_hidden;
      ++total;
      if (is_hidden) {
        ++run[m];
      } else if (run[m] > 0) {
        ++runs;
        run_frames += run[m];
        run[m] = 0;
      }
    }
  }
  EXPECT_NEAR(static_cast<double>(hidden) / total, 0.1, 0.025);
  ASSERT_GT(runs, 50);
  EXPECT_NEAR(static_cast<double>(run_frames) / runs, 8.0, 1.5);
}

TEST(ProjectorTest, DroppedFramesAndVisibilityCounts) {
  const Scene scene = MakeScene(1500, 5);
  ProjectOptions options;
  options.drop_frames = 0.2;
  FaultyProjector projector(scene.rig, 5, options);
  std::vector<int> seeing;
  size_t delivered = 0;
  for (size_t f = 0; f < scene.motion.NumFrames(); ++f) {
    const auto frames = projector.Project(f, 0, &scene.motion.points[f * 5], &seeing);
    delivered += frames.size();
    for (int count : seeing) EXPECT_EQ(count, static_cast<int>(frames.size()));
  }
  EXPECT_NEAR(1.0 - static_cast<double>(delivered) / (4 * 1500), 0.2, 0.02);
}

TEST(ProjectorTest, SpuriousHalfStaticHalfFlicker) {
  const Scene scene = MakeScene(1, 1);
  ProjectOptions options;
  options.spurious = 4.0;
  FaultyProjector projector(scene.rig, 1, options);
  const Eigen::Vector3d nothing = MarkerTrajectories::Gap();
  std::vector<int> seeing;
  std::map<std::pair<long, long>, int> positions;  // camera 0 blob positions, 0.1 px cells
  size_t blobs = 0;
  const int frames = 2000;
  for (int f = 0; f < frames; ++f) {
    const auto out = projector.Project(f, 0, &nothing, &seeing);
    for (const CameraFrame& frame : out) blobs += frame.blobs.size();
    for (const Blob& blob : out[0].blobs) {
      ++positions[{std::lround(blob.pixel.x() * 10), std::lround(blob.pixel.y() * 10)}];
    }
  }
  EXPECT_NEAR(static_cast<double>(blobs) / (4.0 * frames), 4.0, 0.1);
  int static_spots = 0;
  for (const auto& [cell, count] : positions) static_spots += count == frames ? 1 : 0;
  EXPECT_EQ(static_spots, 2);
}

TEST(ProjectorTest, CloseMarkersMergeAndBlobSizeFollowsDistance) {
  const Scene scene = MakeScene(1, 1);
  const Camera& camera = scene.rig.cameras[0];
  const Eigen::Vector3d forward = camera.rotation.row(2).transpose();
  const Eigen::Vector3d right = camera.rotation.row(0).transpose();
  const Eigen::Vector3d near_point = camera.CenterInWorld() + 2000.0 * forward;
  // Two markers 10 mm apart side by side (14 mm blobs overlap into an elongated blob), one far away.
  const std::vector<Eigen::Vector3d> points = {near_point, near_point + 10.0 * right,
                                               camera.CenterInWorld() + 6000.0 * forward + 400.0 * right};
  std::vector<int> seeing;
  ProjectOptions options;
  FaultyProjector realistic(scene.rig, 3, options);
  const CameraFrame merged = realistic.Project(0, 0, points.data(), &seeing)[0];
  ASSERT_EQ(merged.blobs.size(), 2u);
  const Blob* pair = merged.blobs[0].flags & kBlobMerged ? &merged.blobs[0] : &merged.blobs[1];
  const Blob* far = pair == &merged.blobs[0] ? &merged.blobs[1] : &merged.blobs[0];
  ASSERT_TRUE(pair->flags & kBlobMerged);
  Eigen::Vector2d a, b;
  camera.ProjectToPixel(points[0], &a);
  camera.ProjectToPixel(points[1], &b);
  EXPECT_LT((pair->pixel - 0.5 * (a + b)).norm(), 1e-6);
  EXPECT_EQ(seeing[0], 4);
  // A blob's area falls with the square of distance: 3x farther, ~9x smaller per marker.
  EXPECT_GT(pair->area, 2 * 6 * far->area);
  EXPECT_DOUBLE_EQ(realistic.BlobRadiusPx(camera, 2000.0), 3.0 * realistic.BlobRadiusPx(camera, 6000.0));

  options.merge_px = 0.0;
  FaultyProjector separate(scene.rig, 3, options);
  EXPECT_EQ(separate.Project(0, 0, points.data(), &seeing)[0].blobs.size(), 3u);

  // 4 mm apart the pair still merges but looks round: the node cannot tell, so it is not flagged.
  const std::vector<Eigen::Vector3d> close = {near_point, near_point + 4.0 * right, points[2]};
  const CameraFrame round = realistic.Project(0, 0, close.data(), &seeing)[0];
  ASSERT_EQ(round.blobs.size(), 2u);
  EXPECT_FALSE((round.blobs[0].flags | round.blobs[1].flags) & kBlobMerged);
}

TEST(ProjectorTest, BehindOrOutsideIsNotSeenAndSeedsReplay) {
  const Scene scene = MakeScene(1, 1);
  const Camera& camera = scene.rig.cameras[0];
  const Eigen::Vector3d forward = camera.rotation.row(2).transpose();
  const Eigen::Vector3d right = camera.rotation.row(0).transpose();
  const std::vector<Eigen::Vector3d> points = {camera.CenterInWorld() - 1000.0 * forward,
                                               camera.CenterInWorld() + 1000.0 * forward + 5000.0 * right};
  ProjectOptions options;
  options.merge_px = 0.0;
  FaultyProjector projector(scene.rig, 2, options);
  std::vector<int> seeing;
  EXPECT_TRUE(projector.Project(0, 0, points.data(), &seeing)[0].blobs.empty());

  options.noise_px = 0.2;
  options.spurious = 3;
  options.occlusion = 0.2;
  options.drop_frames = 0.1;
  options.seed = 77;
  FaultyProjector first(scene.rig, 1, options), second(scene.rig, 1, options);
  for (int f = 0; f < 50; ++f) {
    const auto a = first.Project(f, 0, &scene.motion.points[0], &seeing);
    const auto b = second.Project(f, 0, &scene.motion.points[0], &seeing);
    ASSERT_EQ(a.size(), b.size());
    for (size_t c = 0; c < a.size(); ++c) {
      ASSERT_EQ(a[c].blobs.size(), b[c].blobs.size());
      for (size_t k = 0; k < a[c].blobs.size(); ++k) EXPECT_EQ(a[c].blobs[k].pixel, b[c].blobs[k].pixel);
    }
  }
}

TEST(ProjectorTest, EachBlobNamesTheMarkerThatMadeIt) {
  const Scene scene = MakeScene(5);
  ProjectOptions options;
  options.noise_px = 0.05;
  options.spurious = 3.0;
  options.merge_px = 0.0;  // no merging: every marker blob is one marker's
  FaultyProjector projector(scene.rig, scene.motion.NumMarkers(), options);
  std::vector<int> seeing;
  std::vector<std::vector<int>> markers;
  const std::vector<CameraFrame> frames =
      projector.Project(4, 0, &scene.motion.points[4 * scene.motion.NumMarkers()], &seeing, &markers);
  ASSERT_EQ(markers.size(), frames.size());
  int spurious = 0, real = 0;
  for (size_t f = 0; f < frames.size(); ++f) {
    const Camera& camera = scene.rig.cameras[f];
    ASSERT_EQ(markers[f].size(), frames[f].blobs.size());
    for (size_t b = 0; b < frames[f].blobs.size(); ++b) {
      const int m = markers[f][b];
      if (m < 0) {
        ++spurious;
        continue;
      }
      ++real;
      Eigen::Vector2d pixel;
      ASSERT_TRUE(camera.ProjectToPixel(scene.motion.At(4, static_cast<size_t>(m)), &pixel));
      EXPECT_LT((pixel - frames[f].blobs[b].pixel).norm(), 0.5) << "camera " << f << " blob " << b;
    }
  }
  EXPECT_GT(real, 0);
  EXPECT_GE(spurious, static_cast<int>(frames.size()));  // the static half: one per camera at least
}

TEST(ProjectorTest, OptionsChecked) {
  const Scene scene = MakeScene(1, 1);
  const auto rejects = [&](auto change) {
    ProjectOptions options;
    change(options);
    EXPECT_THROW(FaultyProjector(scene.rig, 1, options), std::invalid_argument);
  };
  rejects([](ProjectOptions& o) { o.noise_px = -1; });
  rejects([](ProjectOptions& o) { o.occlusion = 1.0; });
  rejects([](ProjectOptions& o) { o.occlusion_frames = 0.5; });
  rejects([](ProjectOptions& o) { o.spurious = -2; });
  rejects([](ProjectOptions& o) { o.drop_frames = 1.5; });
  rejects([](ProjectOptions& o) { o.merge_px = std::nan(""); });
}

}  // namespace
}  // namespace mocap

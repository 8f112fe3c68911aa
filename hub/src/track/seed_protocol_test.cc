// Seed 001's section 6.1 protocol, end to end with the defaults (no gate given): 33 random points
// in a 497.843 x 788.865 x 748.485 mm box, four 640 x 480 cameras around it, 2 px centroid noise,
// about one view in four hidden. Each random set is held still for 8 frames and scored from its
// 4th: the share of the points seen by two or more cameras that the frame's result (every point
// published, as `serve` publishes it) has within 20 mm, and its points near no point. Prints the
// figures (tools/seed-rigs/paper001.py runs the protocol through the command line). The paper's
// 99.2 % is not reached (about 81 %, 4.6 ghosts per frame, recon README): the test holds what is
// reached and that the noise is measured without an option.
#include <cmath>
#include <cstdio>
#include <map>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "recon/reconstructor.h"
#include "simcore/test_scenes.h"

namespace mocap {
namespace {

constexpr int kPoints = 33;
constexpr int kHold = 8;
constexpr int kScoredFrom = 3;

Camera WebcamAt(uint32_t id, const Eigen::Vector3d& centre, const Eigen::Vector3d& target) {
  Camera camera = testing::LookAtCamera(id, centre, target);
  camera.intrinsics.width = 640;
  camera.intrinsics.height = 480;
  camera.intrinsics.fx = camera.intrinsics.fy = 457.0;  // 70 degrees across
  camera.intrinsics.cx = 320.0;
  camera.intrinsics.cy = 240.0;
  return camera;
}

struct ProtocolFigures {
  long long seen = 0, found = 0, ghosts = 0, frames = 0, views = 0, hidden = 0;
  double noise_px = 0.0;  // what the reconstruction measured
};

void RunProtocol(uint32_t seed, int sets, ProtocolFigures* figures) {
  const Eigen::Vector3d centre(0, 0, 900);
  Rig rig;
  for (int c = 0; c < 4; ++c) {
    const double angle = (0.25 + 0.5 * c) * 3.14159265358979;
    rig.cameras.push_back(WebcamAt(static_cast<uint32_t>(c + 1),
                                   Eigen::Vector3d(1800 * std::cos(angle), 1800 * std::sin(angle), 1900), centre));
  }
  testing::ProjectionFaults faults;
  faults.noise_px = 2.0;
  faults.occlusion = 0.042;  // with 8-frame occlusions: about a quarter of the views hidden
  faults.occlusion_frames = kHold;
  testing::FrameProjector projector(rig, faults, seed);
  // Every frame matched from scratch, no tracker: a set's points jump to new random places every
  // 8 frames, where a tracker's predictions (still points) would serve other points' blobs.
  ReconstructorOptions recon_options;
  recon_options.use_predictions = false;
  Reconstructor reconstructor(rig, recon_options);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> x(-248.9215, 248.9215), y(-394.4325, 394.4325), z(525.7575, 1274.2425);
  std::vector<std::vector<Eigen::Vector3d>> truth;
  std::vector<std::vector<int>> views;
  std::map<uint64_t, std::vector<Eigen::Vector3d>> live;
  FrameSet frame_set;
  testing::BlobTruth blob_truth;
  std::vector<ReconstructedPoint> points;
  std::vector<Eigen::Vector3d> set(kPoints);
  const int frames = sets * kHold;
  for (int f = 0; f < frames; ++f) {
    if (f % kHold == 0) {
      for (Eigen::Vector3d& p : set) p = Eigen::Vector3d(x(rng), y(rng), z(rng));
    }
    truth.push_back(set);
    projector.Project(f, set, &frame_set, &blob_truth);
    views.emplace_back(kPoints, 0);
    for (const std::vector<int>& camera : blob_truth) {
      for (int m : camera) {
        if (m >= 0) ++views.back()[m];
      }
    }
    reconstructor.Process(frame_set, {}, &points);
    for (const ReconstructedPoint& p : points) live[f].push_back(p.point_in_world);
  }
  figures->noise_px = reconstructor.centroid_noise_px();
  for (int f = 0; f < frames; ++f) {
    if (f % kHold < kScoredFrom) continue;
    ++figures->frames;
    const std::vector<Eigen::Vector3d>& row = live[f];
    std::vector<char> taken(row.size(), 0);
    for (int m = 0; m < kPoints; ++m) {
      figures->views += 4;
      figures->hidden += 4 - views[f][m];
      // Nearest free output point within 20 mm (sets are random: points ~100 mm apart).
      int best = -1;
      double best_d = 20.0;
      for (size_t i = 0; i < row.size(); ++i) {
        const double d = (row[i] - truth[f][m]).norm();
        if (!taken[i] && d < best_d) {
          best = static_cast<int>(i);
          best_d = d;
        }
      }
      if (best >= 0) taken[best] = 1;
      if (views[f][m] < 2) continue;
      ++figures->seen;
      figures->found += best >= 0;
    }
    for (char t : taken) figures->ghosts += !t;
  }
}

TEST(SeedProtocol, Paper001RandomPointsFourWebcams) {
  ProtocolFigures all;
  for (uint32_t seed : {1u, 2u, 3u}) {
    ProtocolFigures figures;
    RunProtocol(seed, 40, &figures);
    std::printf("seed %u: %.2f %% of %lld points found, %.3f ghosts/frame, %.1f %% of views hidden, noise %.2f px\n",
                seed, 100.0 * figures.found / figures.seen, figures.seen,
                static_cast<double>(figures.ghosts) / figures.frames, 100.0 * figures.hidden / figures.views,
                figures.noise_px);
    EXPECT_NEAR(figures.noise_px, 2.0, 0.2);
    all.seen += figures.seen;
    all.found += figures.found;
    all.ghosts += figures.ghosts;
    all.frames += figures.frames;
  }
  const double found = static_cast<double>(all.found) / all.seen;
  const double ghosts = static_cast<double>(all.ghosts) / all.frames;
  std::printf("all: %.2f %% found, %.3f ghosts/frame\n", 100.0 * found, ghosts);
  EXPECT_GT(found, 0.75);
  EXPECT_LT(ghosts, 6.0);
}

}  // namespace
}  // namespace mocap

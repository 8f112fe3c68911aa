// Blob index: every query answers what a scan of all the camera's blobs answers, for crowded and
// sparse images, blobs at one spot, radii from a fraction of a cell to most of the image, query
// points off the grid, and builds that reuse the index for another frame.
#include "recon/blob_index.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <set>

#include <gtest/gtest.h>

#include "simcore/test_scenes.h"

namespace mocap {
namespace {

constexpr int kCameras = 4;

// Camera c holds blobs_per_camera[c] blobs in normalized coordinates (the ring's focal length
// makes ~1000 px per unit): most crowd a subject's patch, some spread over the image, some sit
// exactly on another blob's spot (merged blobs, repeated centroids).
FrameViews RandomViews(std::mt19937* random, const std::vector<int>& blobs_per_camera) {
  FrameViews views;
  std::uniform_real_distribution<double> image(-0.6, 0.6), subject(-0.05, 0.05), unit(0.0, 1.0);
  for (int c = 0; c < kCameras; ++c) {
    views.camera_begin.push_back(views.NumObservations());
    const Eigen::Vector2d patch(image(*random), image(*random));
    for (int b = 0; b < blobs_per_camera[c]; ++b) {
      Observation observation;
      observation.camera = c;
      observation.blob = b;
      const double kind = unit(*random);
      if (kind < 0.6) {
        observation.normalized = patch + Eigen::Vector2d(subject(*random), subject(*random));
      } else if (kind < 0.8 || b == 0) {
        observation.normalized = Eigen::Vector2d(image(*random), image(*random));
      } else {
        observation.normalized = views.observations[views.camera_begin[c] + b / 2].normalized;
      }
      views.observations.push_back(observation);
    }
  }
  views.camera_begin.push_back(views.NumObservations());
  return views;
}

// What the index must answer, by a scan of every blob of the camera.
int ScanNearest(const FrameViews& views, int camera, const Eigen::Vector2d& at, double radius,
                const std::vector<char>& taken) {
  int best = -1;
  double best_distance = radius * radius;
  for (int o = views.camera_begin[camera]; o < views.camera_begin[camera + 1]; ++o) {
    if (taken[o]) continue;
    const double d2 = (views.observations[o].normalized - at).squaredNorm();
    if (d2 < best_distance || (d2 == best_distance && best < 0)) {
      best = o;
      best_distance = d2;
    }
  }
  return best;
}

std::set<int> ScanWithin(const FrameViews& views, int camera, const Eigen::Vector2d& at, double radius) {
  std::set<int> within;
  for (int o = views.camera_begin[camera]; o < views.camera_begin[camera + 1]; ++o) {
    if ((views.observations[o].normalized - at).norm() <= radius) within.insert(o);
  }
  return within;
}

TEST(BlobIndex, AnswersWhatAScanOfEveryBlobAnswers) {
  const Rig rig = testing::MakeRingRig(kCameras, 4000.0, 2200.0, Eigen::Vector3d(0, 0, 1000));
  const RigModel model(rig);
  std::mt19937 random(7);
  std::uniform_int_distribution<int> blob_count(0, 150);
  std::uniform_real_distribution<double> unit(0.0, 1.0), log_radius(std::log(1e-4), std::log(0.8));
  BlobIndex index;  // one index for every frame: builds must not see an earlier frame's blobs
  long long queries = 0, found = 0, within = 0;
  for (int frame = 0; frame < 300; ++frame) {
    std::vector<int> blobs_per_camera(kCameras);
    for (int& count : blobs_per_camera) count = unit(random) < 0.1 ? static_cast<int>(unit(random) * 2) : blob_count(random);
    const FrameViews views = RandomViews(&random, blobs_per_camera);
    index.Build(model, views);
    std::vector<char> taken(views.observations.size());
    for (char& t : taken) t = unit(random) < 0.2;
    for (int q = 0; q < 200; ++q) {
      const int camera = static_cast<int>(unit(random) * kCameras);
      const double radius = std::exp(log_radius(random));
      Eigen::Vector2d at(2.0 * unit(random) - 1.0, 2.0 * unit(random) - 1.0);
      const int size = views.camera_begin[camera + 1] - views.camera_begin[camera];
      if (size > 0 && unit(random) < 0.7) {
        // Near a blob, as a prediction's reprojection is: on it, or within a few radii.
        const Eigen::Vector2d blob = views.observations[views.camera_begin[camera] + static_cast<int>(unit(random) * size)].normalized;
        at = blob + (unit(random) < 0.2 ? 0.0 : 3.0 * radius) * Eigen::Vector2d(unit(random) - 0.5, unit(random) - 0.5);
      }
      const std::vector<char> none(views.observations.size(), 0);
      const int nearest = ScanNearest(views, camera, at, radius, none);
      ASSERT_EQ(index.NearestOfAll(camera, at, radius), nearest) << "frame " << frame << " query " << q;
      ASSERT_EQ(index.Nearest(views, camera, at, radius, [](int) { return true; }), nearest);
      ASSERT_EQ(index.Nearest(views, camera, at, radius, [&](int o) { return !taken[o]; }),
                ScanNearest(views, camera, at, radius, taken));
      std::multiset<int> visited;
      index.ForEachWithin(views, camera, at, radius, [&](int o, double distance) {
        EXPECT_DOUBLE_EQ(distance, (views.observations[o].normalized - at).norm());
        visited.insert(o);
      });
      const std::set<int> expected = ScanWithin(views, camera, at, radius);
      ASSERT_EQ(visited, std::multiset<int>(expected.begin(), expected.end()));
      ++queries;
      found += nearest >= 0;
      within += static_cast<long long>(expected.size());
    }
  }
  // The draws must reach both answers often, or the comparison says little.
  EXPECT_GT(found, queries / 3);
  EXPECT_LT(found, queries);
  EXPECT_GT(within, queries);
}

TEST(BlobIndex, RadiiBeyondTheGridOrBelowZero) {
  const Rig rig = testing::MakeRingRig(kCameras, 4000.0, 2200.0, Eigen::Vector3d(0, 0, 1000));
  const RigModel model(rig);
  std::mt19937 random(11);
  const FrameViews views = RandomViews(&random, {40, 1, 0, 90});
  BlobIndex index;
  index.Build(model, views);
  const std::vector<char> none(views.observations.size(), 0);
  const double infinity = std::numeric_limits<double>::infinity();
  for (int camera = 0; camera < kCameras; ++camera) {
    const int size = views.camera_begin[camera + 1] - views.camera_begin[camera];
    // Corners far past what an int holds (from the middle every blob is within reach).
    for (const double radius : {1e9, 1e300, infinity}) {
      for (const Eigen::Vector2d& at : {Eigen::Vector2d(0.0, 0.0), Eigen::Vector2d(-1e9 + 0.2, 3e8)}) {
        const int nearest = ScanNearest(views, camera, at, radius, none);
        if (at.norm() < 1.0) {
          EXPECT_EQ(nearest >= 0, size > 0);
        }
        EXPECT_EQ(index.NearestOfAll(camera, at, radius), nearest) << radius;
        EXPECT_EQ(index.Nearest(views, camera, at, radius, [](int) { return true; }), nearest) << radius;
        int visited = 0;
        index.ForEachWithin(views, camera, at, radius, [&](int, double) { ++visited; });
        EXPECT_EQ(visited, static_cast<int>(ScanWithin(views, camera, at, radius).size())) << radius;
      }
    }
    // A negative or NaN radius reaches nothing, even from on top of a blob.
    if (size == 0) continue;
    const Eigen::Vector2d on_blob = views.observations[views.camera_begin[camera]].normalized;
    for (const double radius : {-0.005, -infinity, std::numeric_limits<double>::quiet_NaN()}) {
      EXPECT_EQ(index.NearestOfAll(camera, on_blob, radius), -1);
      EXPECT_EQ(index.Nearest(views, camera, on_blob, radius, [](int) { return true; }), -1);
      index.ForEachWithin(views, camera, on_blob, radius, [&](int o, double) { ADD_FAILURE() << "visited " << o; });
    }
  }
}

}  // namespace
}  // namespace mocap

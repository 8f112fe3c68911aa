// Tests of `sim render` as a library call: the written frames replay through the framefile
// reader with the motion's frame numbers, the node's detector finds each imaged marker where
// the rig's (distorted) projection puts it, and the side files describe the same session.
#include "sim/frame_render.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "detect/detect.h"
#include "framefile/framefile.h"
#include "io/calibration_json.h"
#include "io/trc.h"
#include "io/visibility.h"
#include "simcore/motion_volume.h"
#include "simcore/ring_rig.h"
#include "simcore/synthetic_motion.h"
#include "util/temporary_directory_testing.h"

namespace mocap {
namespace {

class FrameRenderTest : public ::testing::Test {
 protected:
  void SetUp() override {
    SyntheticMotionOptions m;
    m.markers = 12;
    m.frames = 6;
    m.rate_hz = 100.0;
    m.first_frame = 40;
    motion_ = MakeSyntheticMotion(m);
    RingRigOptions r;
    r.cameras = 3;
    r.width = 640;
    r.height = 400;
    rig_ = MakeRingRig(ComputeMotionVolume(motion_, m.up_axis), r);
  }

  const testing::TemporaryDirectory temp_{"frame_render_test"};
  const std::string dir_ = temp_.path().string();
  MarkerTrajectories motion_;
  Rig rig_;
};

TEST_F(FrameRenderTest, DetectedSpotsLieOnTheProjections) {
  FrameRenderOptions options;
  options.render.noise_sigma = 1.5;
  const FrameRenderStats stats = RenderFrames(motion_, rig_, options, dir_);
  EXPECT_EQ(stats.frames, 6u);
  EXPECT_EQ(stats.camera_frames, 18u);

  mn_detect_config dc;
  mn_detect_config_default(&dc);
  dc.threshold = 32;
  size_t matched = 0, imaged = 0;
  double worst = 0.0;
  for (const Camera& camera : rig_.cameras) {
    const char* why = nullptr;
    mn_ff_reader* reader = mn_ff_reader_open(CameraFramesDir(dir_, camera.id).c_str(), &why);
    ASSERT_NE(reader, nullptr) << why;
    const mn_ff_info* info = mn_ff_reader_info(reader);
    ASSERT_EQ(info->width, 640u);
    EXPECT_EQ(info->rate_mhz, 100000u);
    mn_detector* det = mn_detector_new(&dc, info->width, info->height);
    ASSERT_NE(det, nullptr);
    std::vector<uint8_t> pixels(static_cast<size_t>(info->width) * info->height);
    std::vector<mn_blob> blobs(256);
    mn_ff_frame meta;
    for (size_t f = 0; f < motion_.NumFrames(); ++f) {
      ASSERT_EQ(mn_ff_reader_next(reader, pixels.data(), info->width, &meta), 1);
      // Frame k of the replay is global frame k: the motion's own numbers, from 40 on.
      EXPECT_EQ(meta.frame_number, motion_.frame_numbers[f]);
      size_t n = 0;
      ASSERT_EQ(mn_detector_run(det, pixels.data(), info->width, info->height, info->width, blobs.data(),
                                blobs.size(), &n), 0);
      for (size_t m = 0; m < motion_.NumMarkers(); ++m) {
        Eigen::Vector2d pixel;
        if (!camera.ProjectToPixel(motion_.At(f, m), &pixel) || !camera.InImage(pixel)) continue;
        ++imaged;
        double best = 1e9;
        for (size_t i = 0; i < n; ++i) best = std::min(best, std::hypot(blobs[i].x - pixel.x(), blobs[i].y - pixel.y()));
        if (best < 0.5) {
          ++matched;
          worst = std::max(worst, best);
        }
      }
    }
    EXPECT_EQ(mn_ff_reader_next(reader, pixels.data(), info->width, &meta), 0);
    mn_detector_free(det);
    mn_ff_reader_close(reader);
  }
  ASSERT_GT(imaged, 100u);
  // Markers that touch in an image merge into one blob, as on a real sensor; nearly all others
  // are found to a small fraction of a pixel.
  EXPECT_GT(static_cast<double>(matched), 0.9 * static_cast<double>(imaged));
  EXPECT_LT(worst, 0.3);
}

TEST_F(FrameRenderTest, WritesTruthCalibrationAndVisibility) {
  FrameRenderOptions options;
  options.project.occlusion = 0.3;
  options.project.seed = 5;
  const FrameRenderStats stats = RenderFrames(motion_, rig_, options, dir_);
  const MarkerTrajectories truth = ReadTrc(dir_ + "/truth.trc");
  EXPECT_EQ(truth.frame_numbers, motion_.frame_numbers);
  EXPECT_EQ(LoadRigJson(dir_ + "/calibration.json").cameras.size(), 3u);
  const MarkerVisibility visibility = ReadVisibility(dir_ + "/visibility.tsv");
  ASSERT_EQ(visibility.NumFrames(), motion_.NumFrames());
  uint64_t seen = 0, reconstructible = 0;
  for (size_t f = 0; f < visibility.NumFrames(); ++f) {
    for (size_t m = 0; m < visibility.names.size(); ++m) {
      EXPECT_LE(visibility.At(f, m), 3);
      seen += visibility.At(f, m);
      reconstructible += visibility.At(f, m) >= 2 ? 1 : 0;
    }
  }
  EXPECT_EQ(reconstructible, stats.reconstructible);
  // Occlusion hides about 30 % of the marker images (all markers are in view without it).
  const double all = static_cast<double>(3 * motion_.NumFrames() * motion_.NumMarkers());
  EXPECT_GT(static_cast<double>(seen), 0.5 * all);
  EXPECT_LT(static_cast<double>(seen), 0.85 * all);
}

TEST_F(FrameRenderTest, CompactOnDisk) {
  const FrameRenderStats stats = RenderFrames(motion_, rig_, FrameRenderOptions{}, dir_);
  // Mostly dark frames: only tiles with spots are stored (a raw frame is 256 kB).
  EXPECT_LT(stats.bytes / stats.camera_frames, 256000u / 10);
}

TEST_F(FrameRenderTest, ReflectionsAddStaticSpots) {
  FrameRenderOptions plain, reflective;
  reflective.reflections = 4;
  const FrameRenderStats a = RenderFrames(motion_, rig_, plain, dir_ + "/a");
  const FrameRenderStats b = RenderFrames(motion_, rig_, reflective, dir_ + "/b");
  EXPECT_EQ(b.spots, a.spots + 4 * b.camera_frames);
}

TEST_F(FrameRenderTest, RejectsBadOptions) {
  FrameRenderOptions options;
  options.gain = 0.0;
  EXPECT_THROW(RenderFrames(motion_, rig_, options, dir_), std::invalid_argument);
  options = FrameRenderOptions{};
  options.reflections = -1;
  EXPECT_THROW(RenderFrames(motion_, rig_, options, dir_), std::invalid_argument);
  EXPECT_THROW(RenderFrames(motion_, Rig{}, FrameRenderOptions{}, dir_), std::invalid_argument);
}

}  // namespace
}  // namespace mocap

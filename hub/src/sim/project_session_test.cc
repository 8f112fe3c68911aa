// End-to-end test of `sim project`'s library call: write a session, read it back through the
// ingest SessionReader, and check the blobs are the projections of the truth (within the wire's
// 1/64 px quantisation, or within the requested noise).
#include "sim/project_session.h"

#include <filesystem>
#include <map>

#include <gtest/gtest.h>

#include "ingest/session.h"
#include "io/calibration_json.h"
#include "io/trc.h"
#include "io/visibility.h"
#include "simcore/ring_rig.h"
#include "simcore/synthetic_motion.h"
#include "util/temporary_directory_testing.h"

namespace mocap {
namespace {

struct Readback {
  size_t frame_sets = 0;
  size_t camera_frames = 0;
  double worst_px = 0.0;     // largest distance projection -> nearest blob
  double sum_squares = 0.0;  // of those distances
  size_t samples = 0;
};

Readback ReadBack(const std::string& dir, const MarkerTrajectories& motion, const Rig& rig) {
  Readback result;
  SessionReader reader;
  reader.Open(dir);
  EXPECT_TRUE(reader.warnings().empty());
  EXPECT_EQ(reader.Info().rate_hz, motion.rate_hz);
  EXPECT_EQ(reader.Info().source, "sim project");
  std::map<uint64_t, size_t> frame_index;
  for (size_t f = 0; f < motion.NumFrames(); ++f) frame_index[motion.frame_numbers[f]] = f;
  FrameSet set;
  while (reader.Next(&set)) {
    ++result.frame_sets;
    const auto it = frame_index.find(set.frame_number);
    EXPECT_NE(it, frame_index.end()) << set.frame_number;
    if (it == frame_index.end()) continue;
    for (const CameraFrame& frame : set.cameras) {
      ++result.camera_frames;
      const Camera* camera = rig.Find(frame.camera_id);
      EXPECT_NE(camera, nullptr);
      if (camera == nullptr) continue;
      EXPECT_EQ(frame.trigger_time_ns,
                kSimEpochNs + static_cast<uint64_t>(std::llround(set.frame_number * 1e9 / motion.rate_hz)));
      for (size_t m = 0; m < motion.NumMarkers(); ++m) {
        Eigen::Vector2d pixel;
        if (!camera->ProjectToPixel(motion.At(it->second, m), &pixel)) continue;
        double best = 1e300;
        for (const Blob& blob : frame.blobs) best = std::min(best, (blob.pixel - pixel).norm());
        result.worst_px = std::max(result.worst_px, best);
        result.sum_squares += best * best;
        ++result.samples;
      }
    }
  }
  return result;
}

class ProjectSessionTest : public ::testing::Test {
 protected:
  void SetUp() override {
    SyntheticMotionOptions motion_options;
    motion_options.frames = 90;
    motion_options.markers = 15;
    motion_options.first_frame = 500;
    motion = MakeSyntheticMotion(motion_options);
    RingRigOptions rig_options;
    rig_options.cameras = 5;
    rig = MakeRingRig(ComputeMotionVolume(motion), rig_options);
  }

  MarkerTrajectories motion;
  Rig rig;
  const testing::TemporaryDirectory temp{"sim_session"};
  const std::string dir = temp.File("session");  // made by ProjectSession
};

TEST_F(ProjectSessionTest, BlobsReadBackAsProjections) {
  ProjectOptions options;
  options.merge_px = 0.0;
  size_t progress_calls = 0;
  const ProjectSessionStats stats =
      ProjectSession(motion, rig, options, dir, [&](size_t done, size_t total) {
        ++progress_calls;
        EXPECT_EQ(total, 90u);
        EXPECT_EQ(done, progress_calls);
      });
  EXPECT_EQ(progress_calls, 90u);
  EXPECT_EQ(stats.frames, 90u);
  EXPECT_EQ(stats.camera_frames, 450u);
  EXPECT_EQ(stats.blobs, 450u * 15u);
  EXPECT_EQ(stats.reconstructible, stats.present);

  const Readback back = ReadBack(dir, motion, rig);
  EXPECT_EQ(back.frame_sets, 90u);
  EXPECT_EQ(back.camera_frames, 450u);
  EXPECT_EQ(back.samples, 450u * 15u);
  EXPECT_LE(back.worst_px, 0.5 / 64.0 * std::sqrt(2.0) + 1e-9);

  // The files beside the log: the truth, the rig and the visibility.
  const MarkerTrajectories truth = ReadTrc(dir + "/truth.trc");
  EXPECT_EQ(truth.frame_numbers, motion.frame_numbers);
  EXPECT_EQ(truth.names, motion.names);
  const Rig saved = LoadRigJson(dir + "/calibration.json");
  ASSERT_EQ(saved.cameras.size(), 5u);
  EXPECT_EQ(saved.cameras[2].translation, rig.cameras[2].translation);
  const MarkerVisibility visibility = ReadVisibility(dir + "/visibility.tsv");
  EXPECT_EQ(visibility.frame_numbers, motion.frame_numbers);
  for (uint16_t count : visibility.counts) EXPECT_EQ(count, 5);
  const SessionInfo info = LoadSessionInfo(dir);
  EXPECT_EQ(info.camera_ids, (std::vector<uint32_t>{1, 2, 3, 4, 5}));
  EXPECT_EQ(info.frame_sets, 90u);
  EXPECT_EQ(info.camera_frames, 450u);
}

// A bump halfway: the blobs follow the rig given until then and the bumped rig after it, while
// calibration.json stays the rig given and truth.calibration.json is the bumped one.
TEST_F(ProjectSessionTest, BumpedCameraSeesFromItsNewPoseAfterTheBump) {
  ProjectOptions options;
  options.merge_px = 0.0;
  CameraBump bump = ParseCameraBump("2:1:20");
  bump.from_s = 45.0 / motion.rate_hz;
  bump.seed = 4;
  ProjectSession(motion, rig, options, dir, nullptr, {bump});
  const Rig calibration = LoadRigJson(dir + "/calibration.json");
  const Rig truth = LoadRigJson(dir + "/truth.calibration.json");
  EXPECT_EQ(calibration.cameras[1].translation, rig.cameras[1].translation);
  EXPECT_NEAR(ComparePoses(truth.cameras[1], rig.cameras[1]).rotation_deg, 1.0, 1e-9);
  EXPECT_EQ(truth.cameras[0].translation, rig.cameras[0].translation);
  const SessionInfo info = LoadSessionInfo(dir);
  ASSERT_TRUE(info.extra["sim"].contains("bumps"));
  EXPECT_EQ(info.extra["sim"]["bumps"][0]["camera"], 2);

  SessionReader reader;
  reader.Open(dir);
  FrameSet set;
  size_t frames_checked = 0;
  while (reader.Next(&set)) {
    const bool after = set.frame_number >= motion.frame_numbers[45];
    const size_t index = set.frame_number - motion.frame_numbers[0];
    for (const CameraFrame& frame : set.cameras) {
      if (frame.camera_id != 2) continue;
      double worst_before = 0.0, worst_after = 0.0;
      for (size_t m = 0; m < motion.NumMarkers(); ++m) {
        Eigen::Vector2d old_pixel, new_pixel;
        ASSERT_TRUE(rig.cameras[1].ProjectToPixel(motion.At(index, m), &old_pixel));
        ASSERT_TRUE(truth.cameras[1].ProjectToPixel(motion.At(index, m), &new_pixel));
        double nearest_old = 1e300, nearest_new = 1e300;
        for (const Blob& blob : frame.blobs) {
          nearest_old = std::min(nearest_old, (blob.pixel - old_pixel).norm());
          nearest_new = std::min(nearest_new, (blob.pixel - new_pixel).norm());
        }
        worst_before = std::max(worst_before, nearest_old);
        worst_after = std::max(worst_after, nearest_new);
      }
      EXPECT_LE(after ? worst_after : worst_before, 0.02) << "frame " << set.frame_number;
      EXPECT_GT(after ? worst_before : worst_after, 1.0) << "frame " << set.frame_number;
      ++frames_checked;
    }
  }
  EXPECT_EQ(frames_checked, motion.NumFrames());
  EXPECT_THROW(ProjectSession(motion, rig, options, dir + "_bad", nullptr, {ParseCameraBump("9:1:1")}),
               std::invalid_argument);
}

TEST_F(ProjectSessionTest, FaultsReachTheSession) {
  ProjectOptions options;
  options.noise_px = 0.2;
  options.drop_frames = 0.1;
  options.occlusion = 0.05;
  options.spurious = 2;
  options.seed = 5;
  const ProjectSessionStats stats = ProjectSession(motion, rig, options, dir);
  EXPECT_GT(stats.dropped_camera_frames, 20u);
  EXPECT_LT(stats.dropped_camera_frames, 80u);
  EXPECT_EQ(stats.camera_frames + stats.dropped_camera_frames, 450u);
  EXPECT_LT(stats.reconstructible, stats.present);

  const Readback back = ReadBack(dir, motion, rig);
  EXPECT_EQ(back.camera_frames, stats.camera_frames);
  EXPECT_EQ(LoadSessionInfo(dir).dropped_camera_frames, stats.dropped_camera_frames);
  // Visibility counts cameras that delivered a blob, so it is at most the delivered frames.
  const MarkerVisibility visibility = ReadVisibility(dir + "/visibility.tsv");
  size_t below_two = 0;
  for (uint16_t count : visibility.counts) below_two += count < 2;
  EXPECT_EQ(below_two, stats.present - stats.reconstructible);
  EXPECT_GT(back.samples, 0u);
  EXPECT_GT(back.worst_px, 1.0);  // occlusion hides some markers from some cameras
}

TEST_F(ProjectSessionTest, LateFramesStillAssembleInOrder) {
  ProjectOptions options;
  options.merge_px = 0.0;
  options.late = 0.2;
  options.late_frames = 4;
  const ProjectSessionStats stats = ProjectSession(motion, rig, options, dir);
  EXPECT_GT(stats.late_camera_frames, 50u);
  EXPECT_LT(stats.late_camera_frames, 130u);
  // Every frame set still comes out whole and exact, in frame order, within the reader's window.
  const Readback back = ReadBack(dir, motion, rig);
  EXPECT_EQ(back.frame_sets, 90u);
  EXPECT_EQ(back.camera_frames, 450u);
  EXPECT_LE(back.worst_px, 0.5 / 64.0 * std::sqrt(2.0) + 1e-9);
  EXPECT_EQ(LoadSessionInfo(dir).frame_sets, 90u);
}

TEST_F(ProjectSessionTest, SameSeedSameSession) {
  ProjectOptions options;
  options.noise_px = 0.2;
  options.spurious = 3;
  options.occlusion = 0.1;
  options.seed = 9;
  ProjectSession(motion, rig, options, dir + "_a");
  ProjectSession(motion, rig, options, dir + "_b");
  SessionReader a, b;
  a.Open(dir + "_a");
  b.Open(dir + "_b");
  FrameSet set_a, set_b;
  size_t blobs = 0;
  while (a.Next(&set_a)) {
    ASSERT_TRUE(b.Next(&set_b));
    ASSERT_EQ(set_a.cameras.size(), set_b.cameras.size());
    for (size_t c = 0; c < set_a.cameras.size(); ++c) {
      ASSERT_EQ(set_a.cameras[c].blobs.size(), set_b.cameras[c].blobs.size());
      for (size_t k = 0; k < set_a.cameras[c].blobs.size(); ++k) {
        EXPECT_EQ(set_a.cameras[c].blobs[k].pixel, set_b.cameras[c].blobs[k].pixel);
        ++blobs;
      }
    }
  }
  EXPECT_FALSE(b.Next(&set_b));
  EXPECT_GT(blobs, 1000u);
}

}  // namespace
}  // namespace mocap

namespace mocap {
namespace {

// Free-running cameras: each exposes at its own constant phase (no rate error, no jitter here),
// its blobs are the motion at that instant and its stamp says when; with jitter the stamps scatter
// around that instant by the jitter asked.
TEST_F(ProjectSessionTest, FreeRunningCamerasExposeAtTheirOwnPhase) {
  ProjectOptions options;
  options.merge_px = 0.0;
  FreeRunOptions free_run;
  free_run.enabled = true;
  free_run.rate_error_ppm = 0.0;
  free_run.jitter_ms = 0.0;
  ProjectSession(motion, rig, options, dir, nullptr, {}, free_run);
  SessionReader reader;
  reader.Open(dir);
  EXPECT_TRUE(reader.Info().free_run);
  const double period_ns = 1e9 / motion.rate_hz;
  std::map<uint32_t, double> phase;  // camera -> offset from the slot's instant, frame periods
  double worst_px = 0.0;
  size_t samples = 0;
  FrameSet set;
  while (reader.Next(&set)) {
    const size_t f = set.frame_number - motion.frame_numbers[0];
    for (const CameraFrame& frame : set.cameras) {
      EXPECT_EQ(frame.flags & kFrameFreeRun, kFrameFreeRun);
      EXPECT_EQ(frame.trigger_time_ns, 0u);
      const double slot_ns = static_cast<double>(set.frame_number) * period_ns;
      const double offset = (static_cast<double>(static_cast<int64_t>(frame.capture_time_ns - kSimEpochNs)) - slot_ns) /
                            period_ns;
      EXPECT_GE(offset, -0.5);
      EXPECT_LT(offset, 0.5);
      const auto [it, first] = phase.try_emplace(frame.camera_id, offset);
      EXPECT_NEAR(offset, it->second, 1e-6) << "camera " << frame.camera_id << " frame " << set.frame_number;
      if (f == 0 || f + 1 >= motion.NumFrames()) continue;
      const size_t a = offset >= 0.0 ? f : f - 1;
      const double t = offset >= 0.0 ? offset : 1.0 + offset;
      const Camera* camera = rig.Find(frame.camera_id);
      for (size_t m = 0; m < motion.NumMarkers(); ++m) {
        Eigen::Vector2d pixel;
        if (!camera->ProjectToPixel((1.0 - t) * motion.At(a, m) + t * motion.At(a + 1, m), &pixel)) continue;
        double best = 1e300;
        for (const Blob& blob : frame.blobs) best = std::min(best, (blob.pixel - pixel).norm());
        worst_px = std::max(worst_px, best);
        ++samples;
      }
    }
  }
  EXPECT_EQ(phase.size(), 5u);
  double spread = 0.0;
  for (const auto& [camera, offset] : phase) spread = std::max(spread, std::abs(offset - phase.begin()->second));
  EXPECT_GT(spread, 0.05) << "the cameras' phases differ";
  EXPECT_GT(samples, 1000u);
  EXPECT_LE(worst_px, 0.5 / 64.0 * std::sqrt(2.0) + 1e-6);

  // With 1 ms of jitter the stamps scatter about the camera's phase by about that.
  free_run.jitter_ms = 1.0;
  ProjectSession(motion, rig, options, dir, nullptr, {}, free_run);
  SessionReader jittered;
  jittered.Open(dir);
  double sum_sq = 0.0;
  size_t stamps = 0;
  while (jittered.Next(&set)) {
    for (const CameraFrame& frame : set.cameras) {
      const double slot_ns = static_cast<double>(set.frame_number) * period_ns;
      const double error_ns = static_cast<double>(static_cast<int64_t>(frame.capture_time_ns - kSimEpochNs)) - slot_ns -
                              phase.at(frame.camera_id) * period_ns;
      sum_sq += error_ns * error_ns;
      ++stamps;
    }
  }
  ASSERT_EQ(stamps, 450u);
  EXPECT_NEAR(std::sqrt(sum_sq / static_cast<double>(stamps)), 1e6, 0.15e6);

  free_run.jitter_ms = -1.0;
  EXPECT_THROW(ProjectSession(motion, rig, options, dir, nullptr, {}, free_run), std::invalid_argument);
}

}  // namespace
}  // namespace mocap

// Live frame-set assembly: completion, deadlines, late and duplicate frames, free-run grouping.
#include "ingest/frame_set_assembler.h"

#include <stdexcept>

#include <gtest/gtest.h>

namespace mocap {
namespace {

CameraFrame Frame(uint32_t cam, uint64_t number, uint64_t capture_ns = 0) {
  CameraFrame f;
  f.camera_id = cam;
  f.frame_number = number;
  f.capture_time_ns = capture_ns;
  return f;
}

constexpr uint64_t kMs = 1'000'000;

TEST(FrameSetAssembler, CompleteSetLeavesAtOnceIncompleteAtDeadline) {
  FrameSetAssemblerOptions o;
  o.deadline_ns = 10 * kMs;
  FrameSetAssembler a(o, {1, 2, 3});
  EXPECT_TRUE(a.Add(Frame(1, 5), 0));
  EXPECT_TRUE(a.Add(Frame(2, 5), 1 * kMs));
  EXPECT_TRUE(a.Collect(2 * kMs).empty());
  EXPECT_TRUE(a.Add(Frame(3, 5), 3 * kMs));
  auto sets = a.Collect(3 * kMs);
  ASSERT_EQ(sets.size(), 1u);
  EXPECT_EQ(sets[0].cameras.size(), 3u);

  EXPECT_TRUE(a.Add(Frame(1, 6), 4 * kMs));
  EXPECT_TRUE(a.Collect(13 * kMs).empty());
  sets = a.Collect(14 * kMs);
  ASSERT_EQ(sets.size(), 1u);
  EXPECT_EQ(sets[0].frame_number, 6u);
  EXPECT_EQ(a.incomplete_sets(), 1u);
  EXPECT_EQ(a.single_camera_sets(), 1u);  // frame 6 held camera 1 alone

  // Two cameras of three: incomplete but not single; flushed single sets count too.
  EXPECT_TRUE(a.Add(Frame(1, 7), 20 * kMs));
  EXPECT_TRUE(a.Add(Frame(3, 7), 20 * kMs));
  EXPECT_TRUE(a.Add(Frame(2, 8), 21 * kMs));
  EXPECT_EQ(a.Collect(30 * kMs).size(), 1u);  // frame 7 at its deadline, frame 8 not yet
  EXPECT_EQ(a.incomplete_sets(), 2u);
  EXPECT_EQ(a.single_camera_sets(), 1u);
  EXPECT_EQ(a.Flush().size(), 1u);
  EXPECT_EQ(a.incomplete_sets(), 3u);
  EXPECT_EQ(a.single_camera_sets(), 2u);
}

TEST(FrameSetAssembler, ASingleCameraRigHasNoSingleCameraSetsToWarnOf) {
  FrameSetAssembler a(FrameSetAssemblerOptions{}, {4});
  EXPECT_TRUE(a.Add(Frame(4, 1), 0));
  EXPECT_EQ(a.Collect(0).size(), 1u);
  EXPECT_EQ(a.single_camera_sets(), 0u);
}

TEST(FrameSetAssembler, LateAndDuplicateFramesAreDropped) {
  FrameSetAssemblerOptions o;
  o.deadline_ns = 5 * kMs;
  FrameSetAssembler a(o, {1, 2});
  a.Add(Frame(1, 1), 0);
  a.Collect(10 * kMs);
  EXPECT_FALSE(a.Add(Frame(2, 1), 11 * kMs));
  EXPECT_EQ(a.late_frames(), 1u);
  EXPECT_TRUE(a.Add(Frame(1, 2), 12 * kMs));
  EXPECT_FALSE(a.Add(Frame(1, 2), 12 * kMs));
  EXPECT_EQ(a.duplicate_frames(), 1u);
}

TEST(FrameSetAssembler, SetsLeaveInFrameNumberOrder) {
  FrameSetAssemblerOptions o;
  o.deadline_ns = 5 * kMs;
  FrameSetAssembler a(o, {1, 2});
  a.Add(Frame(1, 8), 0);
  a.Add(Frame(1, 9), 1 * kMs);
  a.Add(Frame(2, 9), 1 * kMs);
  EXPECT_TRUE(a.Collect(2 * kMs).empty()) << "9 must wait behind the open 8";
  auto sets = a.Collect(6 * kMs);
  ASSERT_EQ(sets.size(), 2u);
  EXPECT_EQ(sets[0].frame_number, 8u);
  EXPECT_EQ(sets[1].frame_number, 9u);
}

TEST(FrameSetAssembler, FreeRunGroupsByCaptureTime) {
  FrameSetAssemblerOptions o;
  o.free_run = true;
  o.rate_hz = 100.0;
  o.epoch_ns = 1'000'000'000;
  FrameSetAssembler a(o, {1, 2});
  // Unsynchronised cameras: 1.5 ms apart belong together, 10 ms apart do not.
  a.Add(Frame(1, 0, o.epoch_ns + 50 * 10 * kMs), 0);
  a.Add(Frame(2, 0, o.epoch_ns + 50 * 10 * kMs + 1500000), 0);
  a.Add(Frame(1, 0, o.epoch_ns + 51 * 10 * kMs), 0);
  auto sets = a.Flush();
  ASSERT_EQ(sets.size(), 2u);
  EXPECT_EQ(sets[0].frame_number, 50u);
  EXPECT_EQ(sets[0].cameras.size(), 2u);
  EXPECT_EQ(sets[1].frame_number, 51u);
}

TEST(FrameSetAssembler, OptionsAreChecked) {
  FrameSetAssemblerOptions o;
  o.free_run = true;
  EXPECT_THROW(o.Check(), std::invalid_argument);
  o.rate_hz = 60;
  EXPECT_NO_THROW(o.Check());
}

TEST(FrameSetAssembler, FramesOffTheSessionClockNeverMoveTheWindow) {
  FrameSetAssemblerOptions o;
  o.deadline_ns = 10 * kMs;
  o.rate_hz = 100.0;
  o.epoch_ns = 1000 * kMs;
  o.clock_window_ns = 250 * kMs;
  FrameSetAssembler a(o, {1, 2});
  const uint64_t now = o.epoch_ns + 505 * kMs;  // frame 50's trigger was 5 ms ago
  // Forged or mis-clocked numbers: far ahead, 2^62, 1 s ahead, 1 s behind, long past.
  for (uint64_t number : {uint64_t{1'000'000}, uint64_t{1} << 62, uint64_t{150}, uint64_t{0}, uint64_t{200'000'000}})
    EXPECT_FALSE(a.Add(Frame(2, number), now)) << number;
  EXPECT_EQ(a.off_clock_frames(), 5u);
  EXPECT_GT(a.ClockOffsetS(150, now), 0.99);
  EXPECT_LT(a.ClockOffsetS(0, now), -0.5);
  EXPECT_TRUE(a.Collect(now + 100 * kMs).empty());  // nothing was opened by them
  // The real frames around now assemble as if nothing happened.
  EXPECT_TRUE(a.Add(Frame(1, 50), now));
  EXPECT_TRUE(a.Add(Frame(2, 50), now + kMs));
  EXPECT_TRUE(a.Add(Frame(1, 51), now + 10 * kMs));
  EXPECT_TRUE(a.Add(Frame(2, 51), now + 11 * kMs));
  const auto sets = a.Collect(now + 11 * kMs);
  ASSERT_EQ(sets.size(), 2u);
  EXPECT_EQ(sets[0].frame_number, 50u);
  EXPECT_EQ(sets[1].frame_number, 51u);
  EXPECT_EQ(a.late_frames(), 0u);
  EXPECT_EQ(a.incomplete_sets(), 0u);
  // Within the window on either side: a node a little ahead, a frame delayed past its deadline.
  EXPECT_TRUE(a.OnSessionClock(70, now));
  EXPECT_TRUE(a.OnSessionClock(30, now));
  EXPECT_FALSE(a.OnSessionClock(80, now));
  EXPECT_FALSE(a.OnSessionClock(20, now));
}

TEST(FrameSetAssembler, NoSessionClockNoWindow) {
  FrameSetAssemblerOptions o;  // no epoch: nothing to judge a frame number by
  o.rate_hz = 100.0;
  FrameSetAssembler a(o, {1});
  EXPECT_TRUE(a.OnSessionClock(uint64_t{1} << 62, 5 * kMs));
  o.epoch_ns = kMs;
  o.clock_window_ns = 0;  // switched off
  FrameSetAssembler b(o, {1});
  EXPECT_TRUE(b.OnSessionClock(uint64_t{1} << 62, 5 * kMs));
}

}  // namespace
}  // namespace mocap

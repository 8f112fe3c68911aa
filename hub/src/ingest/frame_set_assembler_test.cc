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

}  // namespace
}  // namespace mocap

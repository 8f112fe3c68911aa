// Requests waiting on the loop, without a loop or a socket: each answer reaches its own waiter,
// deadlines end previews with a 504 and blobs waiters with no frame set, and a blobs request is
// answered at once when no frame set came for the wait; a window of frame sets is answered full or,
// at its deadline, with what came.
#include "service/waiters.h"

#include <chrono>

#include <gtest/gtest.h>

#include "service/api_error.h"

namespace mocap::service {
namespace {

constexpr uint64_t kMs = 1'000'000;
constexpr uint64_t kWait = 500 * kMs;

template <typename T>
bool Ready(const std::future<T>& f) {
  return f.wait_for(std::chrono::seconds(0)) == std::future_status::ready;
}

FrameSet Set(uint64_t frame) {
  FrameSet set;
  set.frame_number = frame;
  CameraFrame camera;
  camera.camera_id = 4;
  set.cameras.push_back(camera);
  return set;
}

std::vector<CameraMask> Masks(uint32_t camera) {
  CameraMask mask;
  mask.camera_id = camera;
  return {mask};
}

PreviewImage Image(uint32_t node, bool thresholded) {
  PreviewImage image;
  image.node_id = node;
  image.thresholded = thresholded;
  image.width = 2;
  image.height = 1;
  image.pixels = {1, 2};
  return image;
}

TEST(Waiters, EachRequestOutcomeReachesItsWaiterOnce) {
  Waiters waiters(kWait);
  std::future<RequestResult> a = waiters.ForRequest(7);
  std::future<RequestResult> b = waiters.ForRequest(8);
  RequestResult result;
  result.request_id = 8;
  result.node_id = 3;
  EXPECT_TRUE(waiters.Answer(result));
  EXPECT_FALSE(Ready(a));
  ASSERT_TRUE(Ready(b));
  EXPECT_EQ(b.get().node_id, 3u);
  EXPECT_FALSE(waiters.Answer(result));  // answered already: nobody waits
  result.request_id = 99;
  EXPECT_FALSE(waiters.Answer(result));  // a request nobody asked for (the mask job's)
}

TEST(Waiters, PreviewGoesToTheWaitersOfItsNodeAndMode) {
  Waiters waiters(kWait);
  std::future<PreviewImage> raw = waiters.ForPreview(4, false, 100 * kMs);
  std::future<PreviewImage> thresholded = waiters.ForPreview(4, true, 100 * kMs);
  std::future<PreviewImage> other = waiters.ForPreview(5, false, 100 * kMs);
  waiters.Answer(Image(4, false));
  ASSERT_TRUE(Ready(raw));
  EXPECT_EQ(raw.get().pixels, (std::vector<uint8_t>{1, 2}));
  EXPECT_FALSE(Ready(thresholded));
  EXPECT_FALSE(Ready(other));
}

TEST(Waiters, APreviewPastItsDeadlineFailsWith504) {
  Waiters waiters(kWait);
  std::future<PreviewImage> early = waiters.ForPreview(4, false, 100 * kMs);
  std::future<PreviewImage> late = waiters.ForPreview(5, false, 300 * kMs);
  waiters.Expire(100 * kMs - 1, {});
  EXPECT_FALSE(Ready(early));
  waiters.Expire(100 * kMs, {});
  ASSERT_TRUE(Ready(early));
  try {
    early.get();
    FAIL() << "a preview past its deadline must fail";
  } catch (const ApiError& e) {
    EXPECT_EQ(e.status, 504);
  }
  EXPECT_FALSE(Ready(late));
  waiters.Answer(Image(4, false));  // too late for node 4's waiter: nothing breaks
  EXPECT_FALSE(Ready(late));
}

TEST(Waiters, BlobsAnsweredAtOnceWhenNoFrameSetsFlow) {
  Waiters waiters(kWait);
  std::future<BlobsSnapshot> idle = waiters.ForBlobs(10'000 * kMs, Masks(4));
  ASSERT_TRUE(Ready(idle));
  const BlobsSnapshot s = idle.get();
  EXPECT_FALSE(s.set.has_value());
  ASSERT_EQ(s.masks.size(), 1u);
  EXPECT_EQ(s.masks[0].camera_id, 4u);
}

TEST(Waiters, BlobsWaitForTheNextFrameSetWhileSetsFlow) {
  Waiters waiters(kWait);
  waiters.OnFrameSet(Set(1), {}, 10'000 * kMs);  // nobody waits: nothing kept
  std::future<BlobsSnapshot> a = waiters.ForBlobs(10'000 * kMs + kWait, {});
  std::future<BlobsSnapshot> b = waiters.ForBlobs(10'000 * kMs + kWait, {});
  EXPECT_FALSE(Ready(a));
  waiters.OnFrameSet(Set(2), Masks(5), 10'000 * kMs + kWait + 4 * kMs);
  for (std::future<BlobsSnapshot>* f : {&a, &b}) {
    ASSERT_TRUE(Ready(*f));
    const BlobsSnapshot s = f->get();
    ASSERT_TRUE(s.set.has_value());
    EXPECT_EQ(s.set->frame_number, 2u);
    ASSERT_EQ(s.masks.size(), 1u);
    EXPECT_EQ(s.masks[0].camera_id, 5u);
  }
}

TEST(Waiters, BlobsPastTheirDeadlineGetNoFrameSet) {
  Waiters waiters(kWait);
  waiters.OnFrameSet(Set(1), {}, 10'000 * kMs);
  std::future<BlobsSnapshot> waiting = waiters.ForBlobs(10'100 * kMs, {});
  waiters.Expire(10'100 * kMs + kWait - 1, Masks(4));
  EXPECT_FALSE(Ready(waiting));
  waiters.Expire(10'100 * kMs + kWait, Masks(4));
  ASSERT_TRUE(Ready(waiting));
  const BlobsSnapshot s = waiting.get();
  EXPECT_FALSE(s.set.has_value());
  EXPECT_EQ(s.masks.size(), 1u);
}

TEST(Waiters, AFrameSetWindowIsAnsweredWhenFullInOrder) {
  Waiters waiters(kWait);
  std::future<std::vector<FrameSet>> window = waiters.ForFrameSets(3, 5'000 * kMs);
  waiters.OnFrameSet(Set(7), {}, 10 * kMs);
  waiters.OnFrameSet(Set(8), {}, 20 * kMs);
  EXPECT_FALSE(Ready(window));
  waiters.OnFrameSet(Set(9), {}, 30 * kMs);
  ASSERT_TRUE(Ready(window));
  const std::vector<FrameSet> sets = window.get();
  ASSERT_EQ(sets.size(), 3u);
  EXPECT_EQ(sets[0].frame_number, 7u);
  EXPECT_EQ(sets[2].frame_number, 9u);
  waiters.OnFrameSet(Set(10), {}, 40 * kMs);  // nobody waits: nothing kept
}

TEST(Waiters, AFrameSetWindowPastItsDeadlineGetsWhatCame) {
  Waiters waiters(kWait);
  std::future<std::vector<FrameSet>> window = waiters.ForFrameSets(60, 1'000 * kMs);
  waiters.OnFrameSet(Set(1), {}, 10 * kMs);
  waiters.Expire(1'000 * kMs - 1, {});
  EXPECT_FALSE(Ready(window));
  waiters.Expire(1'000 * kMs, {});
  ASSERT_TRUE(Ready(window));
  EXPECT_EQ(window.get().size(), 1u);
}

}  // namespace
}  // namespace mocap::service

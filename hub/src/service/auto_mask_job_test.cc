// One automatic-mask job without sockets: frame sets collected up to the number wanted, masks
// computed for the known cameras on top of the ones the nodes keep, the answer once every
// request finished, and the failures (time out, no camera with a mask) answered as ApiErrors.
#include "service/auto_mask_job.h"

#include <gtest/gtest.h>

#include "service/api_error.h"

namespace mocap::service {
namespace {

// A frame set of cameras 4 and 5, each seeing one static reflection at (x, 100).
FrameSet Set(uint64_t frame) {
  FrameSet set;
  set.frame_number = frame;
  for (uint32_t camera : {4u, 5u}) {
    CameraFrame c;
    c.camera_id = camera;
    c.frame_number = frame;
    c.width = 1280;
    c.height = 800;
    Blob b;
    b.pixel = Eigen::Vector2d(100.0 * camera, 100.0);
    b.area = 12;
    b.peak = 255;
    b.mean = 200;
    c.blobs.push_back(b);
    set.cameras.push_back(c);
  }
  return set;
}

// The ApiError status the answer carries, 0 when it is a value.
int AnswerStatus(std::future<nlohmann::json>* answer) {
  try {
    answer->get();
  } catch (const ApiError& e) {
    return e.status;
  }
  return 0;
}

TEST(AutoMaskJob, CollectsComputesAndAnswersWhenEveryRequestFinished) {
  AutoMaskJob job(20, 1000);
  std::future<nlohmann::json> answer = job.Answer();
  for (uint64_t f = 0; f < 19; ++f) EXPECT_FALSE(job.Collect(Set(f)));
  EXPECT_TRUE(job.collecting());
  EXPECT_TRUE(job.TimedOut(1000));
  EXPECT_TRUE(job.Collect(Set(19)));
  EXPECT_FALSE(job.collecting());
  EXPECT_FALSE(job.Collect(Set(20))) << "frame sets past the number wanted are not collected";
  EXPECT_FALSE(job.TimedOut(5000)) << "only collection times out";

  CameraMask kept;  // camera 4 already masks a region of its own
  kept.camera_id = 4;
  kept.regions.push_back({10, 10, 5, 5});
  const std::vector<CameraMask>& masks = job.ComputeMasks({kept}, [](uint32_t camera) { return camera == 4; });
  ASSERT_EQ(masks.size(), 1u) << "camera 5 is not known to the registry";
  EXPECT_EQ(masks[0].camera_id, 4u);
  ASSERT_EQ(masks[0].regions.size(), 2u);  // the new region and the kept one
  EXPECT_EQ(masks[0].regions[1].x, 10u);

  job.Sent(77, 4);
  EXPECT_FALSE(job.AllAnswered());
  EXPECT_FALSE(job.Finished(78, {{"request", 78}})) << "not this job's request";
  EXPECT_TRUE(job.Finished(77, {{"request", 77}}));
  ASSERT_TRUE(job.AllAnswered());
  job.Succeed(nlohmann::json::array(), "masks.json");
  const nlohmann::json j = answer.get();
  EXPECT_EQ(j["frames"], 20);
  ASSERT_EQ(j["cameras"].size(), 1u);
  EXPECT_EQ(j["cameras"][0]["camera_id"], 4);
  EXPECT_EQ(j["cameras"][0]["static_blobs_found"], 1);
  EXPECT_EQ(j["cameras"][0]["regions"], 2);
  ASSERT_EQ(j["nodes"].size(), 1u);
  EXPECT_EQ(j["nodes"][0]["request"], 77);
  EXPECT_EQ(j["file"], "masks.json");
}

TEST(AutoMaskJob, NoKnownCameraFailsWith504) {
  AutoMaskJob job(10, 1000);
  std::future<nlohmann::json> answer = job.Answer();
  for (uint64_t f = 0; f < 10; ++f) job.Collect(Set(f));
  EXPECT_TRUE(job.ComputeMasks({}, [](uint32_t) { return false; }).empty());
  EXPECT_EQ(AnswerStatus(&answer), 504);
}

TEST(AutoMaskJob, TimeoutReasonCountsTheFrameSets) {
  AutoMaskJob job(100, 1000);
  std::future<nlohmann::json> answer = job.Answer();
  for (uint64_t f = 0; f < 7; ++f) job.Collect(Set(f));
  EXPECT_FALSE(job.TimedOut(999));
  ASSERT_TRUE(job.TimedOut(1000));
  EXPECT_EQ(job.TimeoutReason(), "only 7 of 100 frame sets arrived in time (are the nodes running?)");
  job.Fail(504, job.TimeoutReason());
  EXPECT_EQ(AnswerStatus(&answer), 504);
}

}  // namespace
}  // namespace mocap::service

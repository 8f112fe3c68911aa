// Live wanding's collecting part without sockets: settings are checked with API errors, a
// simulated wave fills every camera until collection stops by itself, and the timeout stops a
// wave that never covers a camera.
#include "service/wand_collection.h"

#include <gtest/gtest.h>

#include "service/api_error.h"
#include "simcore/test_scenes.h"

namespace mocap::service {
namespace {

constexpr uint64_t kSecond = 1'000'000'000ull;

WandingOptions Options() {
  WandingOptions o;
  o.session = "wand1";
  o.wand_length_mm = 500.0;
  o.min_samples = 100;
  o.coverage_target = 0.3;
  o.timeout_s = 60.0;
  return o;
}

TEST(WandCollection, BadSettingsAreApiErrors) {
  const Rig rig = testing::RingRig(3, 1);
  auto refused = [&](WandingOptions o) {
    try {
      WandCollection c(rig, o, 0);
    } catch (const ApiError& e) {
      return e.status == 400;
    }
    return false;
  };
  WandingOptions o = Options();
  o.session = "../x";
  EXPECT_TRUE(refused(o));
  o = Options();
  o.middle_marker_mm = 500.0;
  EXPECT_TRUE(refused(o));
  o = Options();
  o.refine_intrinsics = "most";
  EXPECT_TRUE(refused(o));
  o = Options();
  o.coverage.rows = 0;
  EXPECT_TRUE(refused(o));
  o = Options();
  o.thresholds.rms_px = {1.0, 0.5, 0.3, 0.2};
  EXPECT_TRUE(refused(o));
  EXPECT_FALSE(refused(Options()));
}

TEST(WandCollection, StopsWhenEveryCameraHasEnough) {
  const Rig rig = testing::RingRig(4, 2);
  const testing::WandScene scene = testing::MakeWandScene(rig, {-250.0, 250.0}, 2000, 0.1, 3);
  WandCollection collection(rig, Options(), 100 * kSecond);
  size_t fed = 0;
  for (const FrameSet& set : scene.frames) {
    collection.Add(set);
    ++fed;
    if (!collection.StopReason(101 * kSecond).empty()) break;
  }
  EXPECT_LT(fed, scene.frames.size());  // stopped before the wave ended
  EXPECT_EQ(collection.StopReason(101 * kSecond), "every camera has enough samples and coverage");
  const nlohmann::json j = collection.Json(101 * kSecond);
  EXPECT_DOUBLE_EQ(j["elapsed_s"].get<double>(), 1.0);
  EXPECT_EQ(j["frame_sets"].get<size_t>(), fed);
  ASSERT_EQ(j["cameras"].size(), 4u);
  for (const auto& c : j["cameras"]) {
    EXPECT_TRUE(c["enough"].get<bool>()) << c.dump();
    EXPECT_GE(c["samples"].get<size_t>(), 100u);
    EXPECT_GE(c["coverage"].get<double>(), 0.3);
    EXPECT_EQ(c["counts"].size(), 48u);  // the default 8 x 6 grid
  }
  EXPECT_TRUE(j["advice"].empty());
}

// A single marker waved fills every camera, but collection goes on (asking for the scale bar)
// until the bar (two markers) has been seen in min_scale_frames frame sets.
TEST(WandCollection, SingleMarkerStopsOnceTheScaleBarWasSeen) {
  const Rig rig = testing::RingRig(4, 2);
  const testing::WandScene marker = testing::MakeWandScene(rig, {0.0}, 2000, 0.1, 5);
  const testing::WandScene bar = testing::MakeWandScene(rig, {-250.0, 250.0}, 400, 0.1, 6);
  WandingOptions o = Options();
  o.mode = kWandingModeSingleMarker;
  o.min_scale_frames = 40;
  WandCollection collection(rig, o, 100 * kSecond);
  for (const FrameSet& set : marker.frames) collection.Add(set);
  EXPECT_EQ(collection.StopReason(101 * kSecond), "");
  nlohmann::json j = collection.Json(101 * kSecond);
  EXPECT_EQ(j["mode"], "single-marker");
  EXPECT_EQ(j["scale_frames"].get<size_t>(), 0u);
  for (const auto& c : j["cameras"]) EXPECT_TRUE(c["enough"].get<bool>()) << c.dump();
  ASSERT_EQ(j["advice"].size(), 1u);
  EXPECT_EQ(j["advice"][0].get<std::string>().rfind("show the scale bar (two markers 500 mm apart)", 0), 0u);
  size_t fed = 0;
  for (const FrameSet& set : bar.frames) {
    collection.Add(set);
    ++fed;
    if (!collection.StopReason(102 * kSecond).empty()) break;
  }
  EXPECT_LT(fed, bar.frames.size());
  EXPECT_EQ(collection.StopReason(102 * kSecond),
            "every camera has enough samples and coverage, and the scale bar was seen");
  j = collection.Json(102 * kSecond);
  EXPECT_EQ(j["scale_frames"].get<size_t>(), 40u);
  EXPECT_TRUE(j["advice"].empty());
  // The wand's collection has no scale bar figures; a single marker takes no middle marker.
  EXPECT_TRUE(WandCollection(rig, Options(), 0).Json(0)["scale_frames"].is_null());
  o.middle_marker_mm = 200.0;
  EXPECT_THROW(WandCollection(rig, o, 0), ApiError);
}

TEST(WandCollection, TimesOutAndAdvisesTheCamerasStillShort) {
  const Rig rig = testing::RingRig(3, 4);
  WandCollection collection(rig, Options(), 10 * kSecond);
  EXPECT_EQ(collection.StopReason(20 * kSecond), "");
  EXPECT_EQ(collection.StopReason(70 * kSecond), "timed out after 60 s");
  const nlohmann::json j = collection.Json(70 * kSecond);
  ASSERT_EQ(j["advice"].size(), 3u);
  EXPECT_EQ(j["advice"][0].get<std::string>().rfind("camera " + std::to_string(rig.cameras[0].id) + ": ", 0), 0u);
}

}  // namespace
}  // namespace mocap::service

// Live wanding's state machine without sockets: what each state allows and refuses (409 with the
// state's name), the collection's figures kept when it stops, a cancel, a solve that fails (its
// session is not on disk) and may be tried again, a fresh start forgetting the last one.
#include "service/live_wanding.h"

#include <chrono>
#include <filesystem>
#include <memory>
#include <string>
#include <thread>

#include <gtest/gtest.h>

#include "service/api_error.h"
#include "simcore/test_scenes.h"

namespace mocap::service {
namespace {

constexpr uint64_t kSecond = 1'000'000'000ull;

WandingOptions Options(const std::string& session) {
  WandingOptions o;
  o.session = session;
  o.wand_length_mm = 500.0;
  o.min_samples = 100;
  o.coverage_target = 0.3;
  o.timeout_s = 60.0;
  return o;
}

// The status of the ApiError `f` throws, and its message in `message`; 0 when it throws none.
template <typename F>
int Refusal(F f, std::string* message = nullptr) {
  try {
    f();
  } catch (const ApiError& e) {
    if (message) *message = e.what();
    return e.status;
  }
  return 0;
}

// Polls until the solve is no longer running; a bound that only catches a hang.
void AwaitSolve(LiveWanding* wanding) {
  for (int i = 0; i < 6000 && wanding->state() == WandingState::kSolving; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
    wanding->Poll();
  }
}

TEST(WandingState, Names) {
  EXPECT_STREQ(WandingStateName(WandingState::kIdle), "idle");
  EXPECT_STREQ(WandingStateName(WandingState::kCollecting), "collecting");
  EXPECT_STREQ(WandingStateName(WandingState::kSolving), "solving");
  EXPECT_STREQ(WandingStateName(WandingState::kSolved), "solved");
  EXPECT_STREQ(WandingStateName(WandingState::kFailed), "failed");
  EXPECT_STREQ(WandingStateName(WandingState::kCancelled), "cancelled");
}

TEST(LiveWanding, IdleRefusesEverythingButStart) {
  const Rig rig = testing::RingRig(3, 1);
  LiveWanding wanding;
  const nlohmann::json j = wanding.Json(0);
  EXPECT_EQ(j["state"], "idle");
  EXPECT_TRUE(j["collection"].is_null());
  EXPECT_TRUE(j["solve"].is_null());
  EXPECT_FALSE(j["applied"].get<bool>());
  std::string why;
  EXPECT_EQ(Refusal([&] { wanding.Stop("x", 0, true, "/nonexistent", rig); }, &why), 409);
  EXPECT_EQ(why, "no wanding is running");
  EXPECT_EQ(Refusal([&] { wanding.SolveAgain("", "/nonexistent", rig); }, &why), 409);
  EXPECT_EQ(why, "no wanding was recorded since serve started");
  EXPECT_EQ(Refusal([&] { wanding.Solved(); }, &why), 409);
  EXPECT_EQ(why, "no solved wand calibration to apply (state idle)");
  EXPECT_EQ(Refusal([&] { wanding.CheckCanStart(); }), 0);
  EXPECT_EQ(wanding.state(), WandingState::kIdle);
}

TEST(LiveWanding, CollectsThenCancelKeepsTheFigures) {
  const Rig rig = testing::RingRig(4, 2);
  const testing::WandScene scene = testing::MakeWandScene(rig, {-250.0, 250.0}, 2000, 0.1, 3);
  LiveWanding wanding;
  wanding.Start(std::make_unique<WandCollection>(rig, Options("wand1"), 100 * kSecond));
  ASSERT_TRUE(wanding.collecting());
  EXPECT_EQ(wanding.options().session, "wand1");
  std::string why;
  EXPECT_EQ(Refusal([&] { wanding.CheckCanStart(); }, &why), 409);
  EXPECT_EQ(why, "wanding wand1 is running already");
  EXPECT_EQ(Refusal([&] { wanding.SolveAgain("", "/nonexistent", rig); }, &why), 409);
  EXPECT_EQ(why, "wanding wand1 is still collecting");
  EXPECT_EQ(Refusal([&] { wanding.Solved(); }, &why), 409);
  EXPECT_EQ(why, "no solved wand calibration to apply (state collecting)");

  size_t fed = 0;
  for (const FrameSet& set : scene.frames) {
    wanding.Add(set);
    ++fed;
    if (!wanding.StopReason(101 * kSecond).empty()) break;
  }
  EXPECT_LT(fed, scene.frames.size());
  EXPECT_EQ(wanding.Json(101 * kSecond)["collection"]["frame_sets"].get<size_t>(), fed);

  wanding.Stop("cancelled on request", 101 * kSecond, false, "/nonexistent", rig);
  EXPECT_EQ(wanding.state(), WandingState::kCancelled);
  const nlohmann::json j = wanding.Json(200 * kSecond);
  EXPECT_EQ(j["state"], "cancelled");
  EXPECT_EQ(j["stop_reason"], "cancelled on request");
  EXPECT_EQ(j["session"], "wand1");
  EXPECT_EQ(j["collection"]["frame_sets"].get<size_t>(), fed);
  EXPECT_DOUBLE_EQ(j["collection"]["elapsed_s"].get<double>(), 1.0) << "the figures of when it stopped";
  EXPECT_TRUE(j["solve"].is_null());
  EXPECT_EQ(Refusal([&] { wanding.Stop("again", 0, false, "/nonexistent", rig); }), 409);
}

TEST(LiveWanding, FailedSolveIsReportedAndMayBeTriedAgain) {
  const Rig rig = testing::RingRig(3, 1);
  const std::string missing = (std::filesystem::temp_directory_path() / "live_wanding_test_no_sessions").string();
  LiveWanding wanding;
  wanding.Start(std::make_unique<WandCollection>(rig, Options("wand2"), 0));
  wanding.Stop("stopped on request", kSecond, true, missing, rig);
  EXPECT_EQ(wanding.state(), WandingState::kSolving);
  std::string why;
  EXPECT_EQ(Refusal([&] { wanding.CheckCanStart(); }, &why), 409);
  EXPECT_EQ(why, "the last wanding is still being solved");
  AwaitSolve(&wanding);
  ASSERT_EQ(wanding.state(), WandingState::kFailed);
  nlohmann::json j = wanding.Json(2 * kSecond);
  EXPECT_EQ(j["state"], "failed");
  EXPECT_FALSE(j["solve"]["ok"].get<bool>());
  EXPECT_FALSE(j["solve"]["error"].get<std::string>().empty());
  EXPECT_TRUE(j["solve"]["files"].is_null());
  EXPECT_EQ(Refusal([&] { wanding.Solved(); }, &why), 409);
  EXPECT_EQ(why, "no solved wand calibration to apply (state failed)");

  wanding.SolveAgain("all", missing, rig);
  EXPECT_EQ(wanding.state(), WandingState::kSolving);
  EXPECT_EQ(wanding.options().refine_intrinsics, "all");
  AwaitSolve(&wanding);
  EXPECT_EQ(wanding.state(), WandingState::kFailed);

  // A new wanding forgets the last one's figures and solve.
  wanding.Start(std::make_unique<WandCollection>(rig, Options("wand3"), 5 * kSecond));
  j = wanding.Json(5 * kSecond);
  EXPECT_EQ(j["state"], "collecting");
  EXPECT_EQ(j["session"], "wand3");
  EXPECT_EQ(j["stop_reason"], "");
  EXPECT_TRUE(j["solve"].is_null());
  EXPECT_EQ(j["collection"]["frame_sets"].get<size_t>(), 0u);
}

}  // namespace
}  // namespace mocap::service

#include "util/worker_team.h"

#include <atomic>
#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>

namespace mocap {
namespace {

TEST(WorkerTeamTest, EveryIndexRunsOnceWhateverTheTeamSize) {
  for (int threads : {1, 2, 4}) {
    WorkerTeam team(threads);
    std::vector<std::atomic<int>> calls(1000);
    team.Run(static_cast<int>(calls.size()), [&](int i) { calls[i].fetch_add(1); });
    for (size_t i = 0; i < calls.size(); ++i) ASSERT_EQ(calls[i].load(), 1) << "index " << i << ", " << threads << " threads";
    team.Run(0, [&](int) { FAIL() << "no index to run"; });
  }
}

TEST(WorkerTeamTest, RefusesAnEmptyTeamAndPassesExceptionsOn) {
  EXPECT_THROW(WorkerTeam(0), std::invalid_argument);
  WorkerTeam team(2);
  EXPECT_THROW(team.Run(100, [](int i) { if (i == 57) throw std::runtime_error("index 57"); }), std::runtime_error);
  std::atomic<int> after{0};
  team.Run(10, [&](int) { after.fetch_add(1); });
  EXPECT_EQ(after.load(), 10);
}

}  // namespace
}  // namespace mocap

// The /api/live query: max_fps in range, nothing else.
#include "api/live_query.h"

#include <gtest/gtest.h>

namespace mocap::api {
namespace {

TEST(LiveQuery, MaxFpsOrEveryFrame) {
  EXPECT_EQ(ParseLiveQuery("")->max_fps, 0);
  EXPECT_EQ(ParseLiveQuery("max_fps=60")->max_fps, 60);
  EXPECT_EQ(ParseLiveQuery("max_fps=1")->max_fps, 1);
  EXPECT_EQ(ParseLiveQuery("max_fps=1000")->max_fps, 1000);
  EXPECT_EQ(ParseLiveQuery("&max_fps=30&")->max_fps, 30);
}

TEST(LiveQuery, AnythingElseIsRefused) {
  for (const char* q : {"max_fps=0", "max_fps=1001", "max_fps=", "max_fps", "max_fps=-5", "max_fps=6.5",
                        "max_fps=99999", "fps=60", "max_fps=60&parts=points", "max_fps=0x10"})
    EXPECT_FALSE(ParseLiveQuery(q).has_value()) << q;
}

}  // namespace
}  // namespace mocap::api

#include "util/thread_priority.h"

#include <gtest/gtest.h>

#include <thread>

namespace mocap {
namespace {

TEST(ThreadPriority, LowersOnlyTheCallingThread) {
  const int before = ThisThreadNice();
  int background = 0, service = 0;
  bool background_ok = false, service_ok = false;
  std::thread([&] {
    background_ok = SetThisThreadPriority(ThreadPriority::kBackground);
    background = ThisThreadNice();
  }).join();
  std::thread([&] {
    service_ok = SetThisThreadPriority(ThreadPriority::kService);
    service = ThisThreadNice();
  }).join();
  EXPECT_TRUE(background_ok);
  EXPECT_TRUE(service_ok);
  EXPECT_EQ(background, 19);
  EXPECT_EQ(service, before > 10 ? before : 10);
  EXPECT_EQ(ThisThreadNice(), before);  // the caller's own thread is untouched
}

TEST(ThreadPriority, NeverRaisesAThreadAlreadyNicer) {
  int after = 0;
  std::thread([&] {
    ASSERT_TRUE(SetThisThreadPriority(ThreadPriority::kBackground));
    EXPECT_TRUE(SetThisThreadPriority(ThreadPriority::kService));  // asks for 10: stays at 19
    after = ThisThreadNice();
  }).join();
  EXPECT_EQ(after, 19);
}

}  // namespace
}  // namespace mocap

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

TEST(ThreadPriority, RealtimeWhereGrantedAndItsChildrenLowerThemselves) {
  std::thread([] {
    EXPECT_FALSE(SetThisThreadRealtime(0));  // out of range: refused, nothing changed
    EXPECT_FALSE(SetThisThreadRealtime(100));
    EXPECT_EQ(ThisThreadRealtimePriority(), 0);
    if (!SetThisThreadRealtime(5)) {
      // Not granted here (no root, CAP_SYS_NICE or RLIMIT_RTPRIO): the thread stays ordinary.
      EXPECT_EQ(ThisThreadRealtimePriority(), 0);
      return;
    }
    EXPECT_EQ(ThisThreadRealtimePriority(), 5);
    int child_inherited = -1, child_after = -1, child_nice = 0;
    std::thread([&] {
      child_inherited = ThisThreadRealtimePriority();
      EXPECT_TRUE(SetThisThreadPriority(ThreadPriority::kBackground));
      child_after = ThisThreadRealtimePriority();
      child_nice = ThisThreadNice();
    }).join();
    EXPECT_EQ(child_inherited, 5);
    EXPECT_EQ(child_after, 0);
    EXPECT_EQ(child_nice, 19);
    EXPECT_EQ(ThisThreadRealtimePriority(), 5);  // the parent keeps its policy
  }).join();
  EXPECT_EQ(ThisThreadRealtimePriority(), 0);  // and the test's own thread never had it
}

}  // namespace
}  // namespace mocap

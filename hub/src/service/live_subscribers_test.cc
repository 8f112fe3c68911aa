#include "service/live_subscribers.h"

#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace mocap::service {
namespace {

using Kind = pipeline::CaptureEvent::Kind;

std::string Describe(const std::vector<pipeline::CaptureEvent>& events) {
  std::string out;
  for (const pipeline::CaptureEvent& e : events) out += (e.kind == Kind::kStarted ? "+" : "-") + e.session + " ";
  return out;
}

TEST(LiveSubscribers, CaptureChangesBecomeEventsOnce) {
  LiveSubscribers s;
  std::vector<pipeline::CaptureEvent> heard;
  s.AddCaptures([&](const pipeline::CaptureEvent& e) { heard.push_back(e); });
  s.NoticeCapture(false, "");
  EXPECT_EQ(Describe(heard), "");  // nothing ran: nothing to tell
  s.NoticeCapture(true, "walk");
  s.NoticeCapture(true, "walk");  // every loop turn: told once
  EXPECT_EQ(Describe(heard), "+walk ");
  s.NoticeCapture(false, "walk");  // the name stays after it ended
  s.NoticeCapture(false, "");
  EXPECT_EQ(Describe(heard), "+walk -walk ");
  s.NoticeCapture(true, "a");
  s.NoticeCapture(true, "b");  // one ended and another started within one turn
  EXPECT_EQ(Describe(heard), "+walk -walk +a -a +b ");
}

TEST(LiveSubscribers, FramesReachEverySubscriberUntilRemoved) {
  LiveSubscribers s;
  std::vector<uint64_t> first, second;
  const int a = s.AddFrames([&](const pipeline::LiveFrame& f) { first.push_back(f.frame_number); });
  const int b = s.AddFrames([&](const pipeline::LiveFrame& f) { second.push_back(f.frame_number); });
  int told = 0;
  const int c = s.AddCaptures([&](const pipeline::CaptureEvent&) { ++told; });
  EXPECT_NE(a, b);
  EXPECT_NE(b, c);
  pipeline::LiveFrame frame;
  frame.frame_number = 7;
  s.Publish(frame);
  s.Remove(a);
  s.Remove(c);
  frame.frame_number = 8;
  s.Publish(frame);
  s.NoticeCapture(true, "x");
  EXPECT_EQ(first, (std::vector<uint64_t>{7}));
  EXPECT_EQ(second, (std::vector<uint64_t>{7, 8}));
  EXPECT_EQ(told, 0);
}

}  // namespace
}  // namespace mocap::service

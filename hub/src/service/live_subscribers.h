// Who hears the live hub: subscribers of every published frame and listeners of its captures
// starting and stopping (pipeline/capture_event.h). The loop publishes each frame and, once a
// turn, tells what the capture is now; a change of it (none -> one, one -> none, one -> another)
// becomes the events, so every way a capture ends (asked, a wanding's, a full disk, shutdown) is
// heard the same. Add and Remove from any thread; Publish and NoticeCapture from the loop, and
// those call back on it (callbacks must return at once).
#pragma once

#include <functional>
#include <map>
#include <mutex>
#include <string>

#include "pipeline/capture_event.h"
#include "pipeline/live_frame.h"

namespace mocap::service {

class LiveSubscribers {
 public:
  using FrameSubscriber = std::function<void(const pipeline::LiveFrame&)>;
  using CaptureListener = std::function<void(const pipeline::CaptureEvent&)>;

  // Each returns an id for Remove; ids are never reused.
  int AddFrames(FrameSubscriber subscriber);
  int AddCaptures(CaptureListener listener);
  void Remove(int id);

  void Publish(const pipeline::LiveFrame& frame);
  // The capture as it is now: `running` and its session name (ignored when none runs).
  void NoticeCapture(bool running, const std::string& session);

 private:
  void Tell(pipeline::CaptureEvent::Kind kind, const std::string& session);

  std::mutex mutex_;
  int next_id_ = 1;
  std::map<int, FrameSubscriber> frames_;
  std::map<int, CaptureListener> captures_;
  std::string capturing_;  // the session last told started, "" when none (session names are never empty)
};

}  // namespace mocap::service

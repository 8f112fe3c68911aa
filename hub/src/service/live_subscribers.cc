#include "service/live_subscribers.h"

namespace mocap::service {

int LiveSubscribers::AddFrames(FrameSubscriber subscriber) {
  std::lock_guard<std::mutex> lock(mutex_);
  frames_[next_id_] = std::move(subscriber);
  return next_id_++;
}

int LiveSubscribers::AddCaptures(CaptureListener listener) {
  std::lock_guard<std::mutex> lock(mutex_);
  captures_[next_id_] = std::move(listener);
  return next_id_++;
}

void LiveSubscribers::Remove(int id) {
  std::lock_guard<std::mutex> lock(mutex_);
  frames_.erase(id);
  captures_.erase(id);
}

void LiveSubscribers::Publish(const pipeline::LiveFrame& frame) {
  std::lock_guard<std::mutex> lock(mutex_);
  for (auto& [id, subscriber] : frames_) subscriber(frame);
}

void LiveSubscribers::NoticeCapture(bool running, const std::string& session) {
  // Called every loop turn: no copy of the name unless the capture changed.
  if (running ? session == capturing_ : capturing_.empty()) return;
  if (!capturing_.empty()) Tell(pipeline::CaptureEvent::Kind::kStopped, capturing_);
  capturing_ = running ? session : std::string();
  if (!capturing_.empty()) Tell(pipeline::CaptureEvent::Kind::kStarted, capturing_);
}

void LiveSubscribers::Tell(pipeline::CaptureEvent::Kind kind, const std::string& session) {
  const pipeline::CaptureEvent event{kind, session};
  std::lock_guard<std::mutex> lock(mutex_);
  for (auto& [id, listener] : captures_) listener(event);
}

}  // namespace mocap::service

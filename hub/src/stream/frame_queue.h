// The hand-over from the hub's loop to one adapter's sending thread: bounded, never blocks the
// producer beyond a short lock, and drops the oldest frame when the adapter falls behind (a
// live stream wants the newest frame, and the loop must never wait for a network peer).
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <mutex>

#include "stream/shared_frame.h"

namespace mocap::stream {

class FrameQueue {
 public:
  explicit FrameQueue(size_t capacity) : capacity_(capacity ? capacity : 1) {}

  void Push(SharedFrame frame) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (closed_) return;
      if (frames_.size() >= capacity_) frames_.pop_front(), ++dropped_;
      frames_.push_back(std::move(frame));
    }
    ready_.notify_one();
  }

  // The oldest queued frame, waiting up to `timeout`; null on timeout or once closed.
  SharedFrame Pop(std::chrono::milliseconds timeout) {
    std::unique_lock<std::mutex> lock(mutex_);
    ready_.wait_for(lock, timeout, [this] { return closed_ || !frames_.empty(); });
    if (closed_ || frames_.empty()) return nullptr;
    SharedFrame frame = std::move(frames_.front());
    frames_.pop_front();
    return frame;
  }

  void Close() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      closed_ = true;
      frames_.clear();
    }
    ready_.notify_all();
  }

  bool closed() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return closed_;
  }

  uint64_t dropped() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return dropped_;
  }

 private:
  const size_t capacity_;
  mutable std::mutex mutex_;
  std::condition_variable ready_;
  std::deque<SharedFrame> frames_;
  uint64_t dropped_ = 0;
  bool closed_ = false;
};

}  // namespace mocap::stream

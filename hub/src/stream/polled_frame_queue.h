// The hand-over to an adapter whose thread waits in poll() over its sockets (NatNet, VRPN,
// Qualisys RT): a FrameQueue plus an eventfd that Push() and Wake() make readable, so a new
// frame ends the poll at once instead of at its timeout.
#pragma once

#include <cstdint>

#include "stream/frame_queue.h"

namespace mocap::stream {

class PolledFrameQueue {
 public:
  // Throws std::runtime_error naming `owner` when the eventfd cannot be made.
  PolledFrameQueue(size_t capacity, const char* owner);
  ~PolledFrameQueue();
  PolledFrameQueue(const PolledFrameQueue&) = delete;
  PolledFrameQueue& operator=(const PolledFrameQueue&) = delete;

  // Queues the frame (dropping the oldest when full) and wakes the poll loop.
  void Push(SharedFrame frame);
  // Wakes the poll loop without a frame (a stop, a changed capture state).
  void Wake();
  // The descriptor to poll for POLLIN.
  int fd() const { return wake_fd_; }
  // After poll() returned: clears the wake-up and hands out the queued frames, oldest first.
  void Acknowledge();
  SharedFrame PopNow() { return queue_.Pop(std::chrono::milliseconds(0)); }
  uint64_t dropped() const { return queue_.dropped(); }

 private:
  FrameQueue queue_;
  int wake_fd_ = -1;
};

}  // namespace mocap::stream

#include "stream/polled_frame_queue.h"

#include <sys/eventfd.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>
#include <string>

namespace mocap::stream {

PolledFrameQueue::PolledFrameQueue(size_t capacity, const char* owner) : queue_(capacity) {
  wake_fd_ = eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC);
  if (wake_fd_ < 0) throw std::runtime_error(std::string(owner) + ": eventfd: " + std::strerror(errno));
}

PolledFrameQueue::~PolledFrameQueue() {
  queue_.Close();
  close(wake_fd_);
}

void PolledFrameQueue::Push(SharedFrame frame) {
  queue_.Push(std::move(frame));
  Wake();
}

void PolledFrameQueue::Wake() {
  const uint64_t one = 1;
  // A full counter (never in practice) still leaves the descriptor readable: nothing to handle.
  (void)!write(wake_fd_, &one, sizeof one);
}

void PolledFrameQueue::Acknowledge() {
  uint64_t count = 0;
  (void)!read(wake_fd_, &count, sizeof count);
}

}  // namespace mocap::stream

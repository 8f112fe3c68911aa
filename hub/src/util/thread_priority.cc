// Thread priorities by nice value: on Linux setpriority(PRIO_PROCESS, tid) changes one thread.
// A nice value is absolute, so a hub started at nice -5 (its systemd unit) gives its background
// threads 19 like any other; the frame loop keeps the process's value.
#include "util/thread_priority.h"

#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <cerrno>

namespace mocap {
namespace {

pid_t ThisThreadId() { return static_cast<pid_t>(syscall(SYS_gettid)); }

int NiceFor(ThreadPriority priority) {
  switch (priority) {
    case ThreadPriority::kBackground:
      return 19;
    case ThreadPriority::kService:
      return 10;
  }
  return 19;
}

}  // namespace

bool SetThisThreadPriority(ThreadPriority priority) {
  const int wanted = NiceFor(priority);
  // Only ever lower: a thread already nicer than asked stays as it is.
  if (ThisThreadNice() >= wanted) return true;
  return setpriority(PRIO_PROCESS, static_cast<id_t>(ThisThreadId()), wanted) == 0;
}

int ThisThreadNice() {
  errno = 0;
  const int nice = getpriority(PRIO_PROCESS, static_cast<id_t>(ThisThreadId()));
  return errno == 0 ? nice : 0;
}

}  // namespace mocap

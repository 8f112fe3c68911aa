// Thread priorities by nice value: on Linux setpriority(PRIO_PROCESS, tid) changes one thread.
// A nice value is absolute, so a hub started at nice -5 (its systemd unit) gives its background
// threads 19 like any other; the frame loop keeps the process's value.
#include "util/thread_priority.h"

#include <pthread.h>
#include <sched.h>
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
  // A thread started by a real-time frame loop inherited its policy: back to the ordinary one
  // (always allowed) before the nice value, which only counts there.
  if (ThisThreadRealtimePriority() > 0) {
    sched_param ordinary{};
    ordinary.sched_priority = 0;
    if (pthread_setschedparam(pthread_self(), SCHED_OTHER, &ordinary) != 0) return false;
  }
  const int wanted = NiceFor(priority);
  // Only ever lower: a thread already nicer than asked stays as it is.
  if (ThisThreadNice() >= wanted) return true;
  return setpriority(PRIO_PROCESS, static_cast<id_t>(ThisThreadId()), wanted) == 0;
}

bool SetThisThreadRealtime(int priority) {
  if (priority < sched_get_priority_min(SCHED_FIFO) || priority > sched_get_priority_max(SCHED_FIFO)) return false;
  sched_param param{};
  param.sched_priority = priority;
  return pthread_setschedparam(pthread_self(), SCHED_FIFO, &param) == 0;
}

int ThisThreadRealtimePriority() {
  int policy = SCHED_OTHER;
  sched_param param{};
  if (pthread_getschedparam(pthread_self(), &policy, &param) != 0) return 0;
  return policy == SCHED_FIFO || policy == SCHED_RR ? param.sched_priority : 0;
}

int ThisThreadNice() {
  errno = 0;
  const int nice = getpriority(PRIO_PROCESS, static_cast<id_t>(ThisThreadId()));
  return errno == 0 ? nice : 0;
}

}  // namespace mocap

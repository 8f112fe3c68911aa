// Scheduling of the live hub's threads: the frame path (receive, reconstruct, publish) must not
// wait behind work that has no deadline (the calibration monitor's checks, wand solves, API
// requests, the console's WebSocket writers). Those threads lower their own priority when they
// start, so that the scheduler hands the CPU back to the frame loop the moment a datagram wakes
// it, on a busy machine or a hub pinned to one core (on Linux a waking thread of normal
// priority otherwise waits up to the scheduler's wake-up granularity, a few ms, behind a busy
// one). Lowering is always allowed. Raising is the operator's choice: the frame loop can run
// under the real-time policy (SCHED_FIFO) when the system grants it (root, CAP_SYS_NICE, or an
// RLIMIT_RTPRIO such as the systemd unit's LimitRTPRIO=), so that no ordinary thread of any
// process delays a frame set; threads it starts afterwards inherit that policy, and the
// background and service ones return to the ordinary one when they lower themselves.
// Threads: each call changes only the calling thread. Errors: returns false (and leaves the
// thread as it was) when the system refuses; the caller decides whether to log it.
#pragma once

namespace mocap {

enum class ThreadPriority {
  kBackground,  // computation without a deadline: runs on what the frame path leaves (nice 19)
  kService,     // requests from people and tools: answered promptly, but after a frame (nice 10)
};

// Sets the calling thread's priority (the ordinary policy at that nice value); false when refused.
bool SetThisThreadPriority(ThreadPriority priority);

// Puts the calling thread under SCHED_FIFO at `priority` (1-99); false (and the thread unchanged)
// when refused or out of range.
bool SetThisThreadRealtime(int priority);
// The calling thread's SCHED_FIFO priority, 0 under the ordinary policy.
int ThisThreadRealtimePriority();

// The calling thread's nice value (for tests and status).
int ThisThreadNice();

}  // namespace mocap

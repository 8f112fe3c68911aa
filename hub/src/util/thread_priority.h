// Scheduling of the live hub's threads: the frame path (receive, reconstruct, publish) must not
// wait behind work that has no deadline (the calibration monitor's checks, wand solves, API
// requests, the console's WebSocket writers). Those threads lower their own priority when they
// start, so that the scheduler hands the CPU back to the frame loop the moment a datagram wakes
// it, on a busy machine or a hub pinned to one core (on Linux a waking thread of normal
// priority otherwise waits up to the scheduler's wake-up granularity, a few ms, behind a busy
// one). Lowering is always allowed; nothing here raises a priority.
// Threads: each call changes only the calling thread. Errors: returns false (and leaves the
// thread as it was) when the system refuses; the caller decides whether to log it.
#pragma once

namespace mocap {

enum class ThreadPriority {
  kBackground,  // computation without a deadline: runs on what the frame path leaves (nice 19)
  kService,     // requests from people and tools: answered promptly, but after a frame (nice 10)
};

// Sets the calling thread's priority; false when refused.
bool SetThisThreadPriority(ThreadPriority priority);

// The calling thread's nice value (for tests and status).
int ThisThreadNice();

}  // namespace mocap

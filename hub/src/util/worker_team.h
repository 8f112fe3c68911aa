// A fixed team of threads for data-parallel loops inside one frame (oneTBB underneath). The
// caller decides what may run in parallel; results must not depend on the team's size.
// Threads: Run blocks the calling thread, which takes part, until every index is done; one
// Run at a time per team. Exceptions thrown by the body reach the caller of Run.
#pragma once

#include <functional>
#include <memory>

namespace mocap {

class WorkerTeam {
 public:
  // threads >= 1; 1 runs every loop on the calling thread without touching oneTBB.
  explicit WorkerTeam(int threads);
  ~WorkerTeam();
  WorkerTeam(const WorkerTeam&) = delete;
  WorkerTeam& operator=(const WorkerTeam&) = delete;

  int threads() const { return threads_; }
  // Calls body(i) once for every i in [0, count), in no particular order.
  void Run(int count, const std::function<void(int)>& body);

 private:
  struct Arena;
  int threads_;
  std::unique_ptr<Arena> arena_;
};

}  // namespace mocap

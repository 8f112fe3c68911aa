// WorkerTeam on a oneTBB task arena limited to the team's size.
#include "util/worker_team.h"

#include <stdexcept>

#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/task_arena.h>

namespace mocap {

struct WorkerTeam::Arena {
  explicit Arena(int threads) : arena(threads) {}
  oneapi::tbb::task_arena arena;
};

WorkerTeam::WorkerTeam(int threads) : threads_(threads) {
  if (threads < 1) throw std::invalid_argument("a worker team needs at least one thread");
  if (threads > 1) arena_ = std::make_unique<Arena>(threads);
}

WorkerTeam::~WorkerTeam() = default;

void WorkerTeam::Run(int count, const std::function<void(int)>& body) {
  if (!arena_ || count <= 1) {
    for (int i = 0; i < count; ++i) body(i);
    return;
  }
  arena_->arena.execute([&] {
    oneapi::tbb::parallel_for(oneapi::tbb::blocked_range<int>(0, count), [&](const oneapi::tbb::blocked_range<int>& range) {
      for (int i = range.begin(); i < range.end(); ++i) body(i);
    });
  });
}

}  // namespace mocap

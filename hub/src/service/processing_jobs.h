// Recorded sessions processed while serve runs (the console's Process button, POST
// /api/sessions/NAME/process): each job applies one processing recipe (pipeline/processing_recipe.h)
// to one session by running `mocap-hub process` in a child process, one job at a time, the others
// queued. A child keeps a long reconstruction's memory and any failure away from the live hub, runs
// under the ordinary scheduling policy at nice 10 (serve's loop may be real-time), and writes what
// the CLI writes: SESSION/processed/RECIPE/ with the results, process.json, and here also
// recipe.json (the recipe as requested, its files resolved), process.log (the command's output) and
// progress.json (cli/progress.h), which Jobs() reads. Never over the raw log, never over earlier
// results unless the request says "overwrite".
//
// A request: {"recipe": {recipe fields, without format and version}, "overwrite": false}. The
// recipe's files ("calibration", "labels", "bodies") are "serve" (the file serve itself was started
// with) or the plain name of a file in the session's directory; nothing else, so a request cannot
// make the hub read a file of its choosing.
//
// Threads: Start and Jobs from the API's threads, Poll from the hub's loop. Errors: ApiError (400
// a refused recipe field, 404 no such session, 409 results already there, the same job queued, too
// many queued); a child that cannot start fails its job with the reason.
#pragma once

#include <sys/types.h>

#include <atomic>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <filesystem>
#include <mutex>
#include <string>

#include <nlohmann/json.hpp>

namespace mocap::service {

struct ProcessingJobsOptions {
  std::string executable;    // the program run as EXECUTABLE process RECIPE SESSION ...
  std::string sessions_dir;  // sessions are its subdirectories
  std::string calibration;   // serve's own files, a request's "serve"; empty: serve has none
  std::string labels;
  std::string bodies;
  size_t max_queued = 16;    // jobs waiting behind the running one
  size_t history = 32;       // finished jobs kept for Jobs()
  void Check() const;        // std::invalid_argument naming the field
};

class ProcessingJobs {
 public:
  explicit ProcessingJobs(ProcessingJobsOptions options);
  ~ProcessingJobs();  // a running child is stopped (SIGTERM) and waited for
  ProcessingJobs(const ProcessingJobs&) = delete;
  ProcessingJobs& operator=(const ProcessingJobs&) = delete;

  // Checks the request and queues the job; answers its description (see Jobs). The session must
  // exist (the caller checks it is complete, not being captured).
  nlohmann::json Start(const std::string& session, const nlohmann::json& request);
  // {"jobs": [{"id", "session", "recipe", "state": queued | running | done | failed, "reason",
  // "progress": {"step", "done", "total"} | null, "exit_status", "log": the last lines of its output,
  // "outputs": the files written (done)}, ...]}, newest first: the queued, the running, the last
  // finished ones.
  nlohmann::json Jobs() const;
  // Whether a job is queued for or running on `session` (it may not be renamed or deleted then).
  bool Uses(const std::string& session) const;
  // Reaps a finished child and starts the next queued job. Called every turn of the hub's loop:
  // without a queued or running job it reads one atomic; with one it looks at most every 50 ms.
  void Poll();

 private:
  struct Job {
    uint64_t id = 0;
    std::string session;
    std::string recipe;
    std::filesystem::path session_dir, output_dir;
    bool overwrite = false;
    std::string state = "queued";
    std::string reason;
    int exit_status = -1;
    pid_t pid = -1;
  };
  nlohmann::json RecipeOf(const std::string& session, const nlohmann::json& request) const;
  std::string FileFor(const std::filesystem::path& session_dir, const std::string& field, const std::string& value,
                      const std::string& serve_file) const;
  void Launch(Job& job);
  void Finish(Job& job, int wait_status);
  nlohmann::json Describe(const Job& job) const;
  void Tidy();  // finished jobs first and at most `history` of them

  const ProcessingJobsOptions options_;
  mutable std::mutex mutex_;
  std::deque<Job> jobs_;  // finished (oldest first), then the running one, then the queued ones
  uint64_t next_id_ = 1;
  std::atomic<size_t> active_{0};  // queued or running jobs
  std::chrono::steady_clock::time_point next_poll_{};
};

}  // namespace mocap::service

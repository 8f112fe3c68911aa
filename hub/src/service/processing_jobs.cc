// Processing jobs: checked requests, a queue, one child at a time (see processing_jobs.h).
#include "service/processing_jobs.h"

#include <fcntl.h>
#include <sched.h>
#include <signal.h>
#include <spawn.h>
#include <sys/resource.h>
#include <sys/wait.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <stdexcept>
#include <vector>

#include "pipeline/processing_recipe.h"
#include "service/api_error.h"
#include "service/session_name.h"
#include "util/regular_file.h"

extern char** environ;

namespace mocap::service {
namespace {

namespace fs = std::filesystem;

constexpr int kChildNice = 10;
constexpr size_t kLogTailBytes = 4096;
constexpr size_t kLogTailLines = 20;
constexpr size_t kSmallFileBytes = 1 << 16;

// The last lines of a child's output, at most kLogTailBytes of them.
nlohmann::json LogTail(const fs::path& log) {
  std::ifstream in(log, std::ios::binary);
  nlohmann::json lines = nlohmann::json::array();
  if (!in) return lines;
  in.seekg(0, std::ios::end);
  const std::streamoff size = in.tellg();
  const std::streamoff from = std::max<std::streamoff>(0, size - static_cast<std::streamoff>(kLogTailBytes));
  in.seekg(from);
  std::string text(static_cast<size_t>(size - from), '\0');
  in.read(text.data(), static_cast<std::streamsize>(text.size()));
  std::vector<std::string> all;
  size_t start = 0;
  for (size_t end; (end = text.find('\n', start)) != std::string::npos; start = end + 1)
    all.push_back(text.substr(start, end - start));
  if (start < text.size()) all.push_back(text.substr(start));
  if (from > 0 && !all.empty()) all.erase(all.begin());  // cut mid-line
  const size_t first = all.size() > kLogTailLines ? all.size() - kLogTailLines : 0;
  for (size_t i = first; i < all.size(); ++i) lines.push_back(all[i]);
  return lines;
}

// A small JSON file the child wrote, or null when it is absent or not (yet) JSON.
nlohmann::json SmallJson(const fs::path& path) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) return nullptr;
  try {
    return nlohmann::json::parse(ReadRegularFile(path.string(), kSmallFileBytes, "a job's file"));
  } catch (const std::exception&) {
    return nullptr;
  }
}

}  // namespace

void ProcessingJobsOptions::Check() const {
  if (executable.empty()) throw std::invalid_argument("processing jobs: 'executable' is empty");
  if (sessions_dir.empty()) throw std::invalid_argument("processing jobs: 'sessions_dir' is empty");
  if (max_queued < 1 || max_queued > 1000)
    throw std::invalid_argument("processing jobs: 'max_queued' " + std::to_string(max_queued) + " is not within 1..1000");
  if (history < 1 || history > 1000)
    throw std::invalid_argument("processing jobs: 'history' " + std::to_string(history) + " is not within 1..1000");
}

ProcessingJobs::ProcessingJobs(ProcessingJobsOptions options) : options_((options.Check(), std::move(options))) {}

ProcessingJobs::~ProcessingJobs() {
  std::lock_guard<std::mutex> lock(mutex_);
  for (Job& job : jobs_) {
    if (job.pid <= 0) continue;
    kill(job.pid, SIGTERM);
    int status = 0;
    while (waitpid(job.pid, &status, 0) < 0 && errno == EINTR) {
    }
  }
}

std::string ProcessingJobs::FileFor(const fs::path& session_dir, const std::string& field, const std::string& value,
                                    const std::string& serve_file) const {
  if (value == "serve") {
    if (serve_file.empty()) throw ApiError(400, "recipe field '" + field + "': serve was started without one");
    return fs::absolute(serve_file).lexically_normal().string();
  }
  if (!ValidSessionName(value))
    throw ApiError(400, "recipe field '" + field + "' must be \"serve\" or the plain name of a file of the session, not '" +
                            value + "'");
  const fs::path path = session_dir / value;
  std::error_code ec;
  if (!fs::is_regular_file(fs::symlink_status(path, ec)))
    throw ApiError(400, "recipe field '" + field + "': the session has no file '" + value + "'");
  return path.string();
}

nlohmann::json ProcessingJobs::RecipeOf(const std::string& session, const nlohmann::json& request) const {
  if (!request.is_object()) throw ApiError(400, "the request must be a JSON object {\"recipe\": {...}, \"overwrite\"}");
  for (const auto& [key, value] : request.items())
    if (key != "recipe" && key != "overwrite") throw ApiError(400, "unknown field '" + key + "'");
  nlohmann::json recipe = request.value("recipe", nlohmann::json::object());
  if (!recipe.is_object()) throw ApiError(400, "'recipe' must be a JSON object of recipe fields");
  if (recipe.contains("format") || recipe.contains("version"))
    throw ApiError(400, "'recipe' takes the recipe's fields only (no format or version)");
  const fs::path session_dir = fs::path(options_.sessions_dir) / session;
  const std::pair<const char*, const std::string*> files[] = {
      {"calibration", &options_.calibration}, {"labels", &options_.labels}, {"bodies", &options_.bodies}};
  for (const auto& [field, serve_file] : files) {
    if (!recipe.contains(field)) continue;
    if (!recipe[field].is_string()) throw ApiError(400, std::string("recipe field '") + field + "' must be a string");
    recipe[field] = FileFor(session_dir, field, recipe[field].get<std::string>(), *serve_file);
  }
  recipe["format"] = "mocap-recipe";
  recipe["version"] = 1;
  try {
    return pipeline::RecipeToJson(pipeline::RecipeFromJson(recipe, "the request"));
  } catch (const std::invalid_argument& error) {
    throw ApiError(400, error.what());
  }
}

nlohmann::json ProcessingJobs::Start(const std::string& session, const nlohmann::json& request) {
  if (!ValidSessionName(session)) throw ApiError(404, "no session '" + session + "'");
  const fs::path session_dir = fs::path(options_.sessions_dir) / session;
  std::error_code ec;
  if (!fs::is_regular_file(session_dir / "session.json", ec)) throw ApiError(404, "no session '" + session + "'");
  const nlohmann::json recipe = RecipeOf(session, request);
  bool overwrite = false;
  if (request.contains("overwrite")) {
    if (!request["overwrite"].is_boolean()) throw ApiError(400, "'overwrite' must be true or false");
    overwrite = request["overwrite"].get<bool>();
  }
  Job job;
  job.session = session;
  job.recipe = recipe["name"].get<std::string>();
  job.session_dir = session_dir;
  job.output_dir = session_dir / "processed" / job.recipe;
  job.overwrite = overwrite;

  std::lock_guard<std::mutex> lock(mutex_);
  size_t waiting = 0;
  for (const Job& other : jobs_) {
    const bool active = other.state == "queued" || other.state == "running";
    waiting += other.state == "queued";
    if (active && other.session == session && other.recipe == job.recipe)
      throw ApiError(409, "session '" + session + "' is already being processed by recipe '" + job.recipe + "' (job " +
                              std::to_string(other.id) + ")");
  }
  if (waiting >= options_.max_queued)
    throw ApiError(409, std::to_string(waiting) + " jobs are queued already; wait for them");
  if (!overwrite && fs::exists(job.output_dir / "process.json", ec))
    throw ApiError(409, "session '" + session + "' already has results of recipe '" + job.recipe +
                            "'; \"overwrite\": true replaces them (the session's own files are never written)");
  fs::create_directories(job.output_dir, ec);
  std::ofstream out(job.output_dir / "recipe.json", std::ios::trunc);
  out << recipe.dump(2) << "\n";
  if (ec || !out) throw ApiError(500, "cannot write " + (job.output_dir / "recipe.json").string() + ": " +
                                       (ec ? ec.message() : std::strerror(errno)));
  fs::remove(job.output_dir / "progress.json", ec);
  job.id = next_id_++;
  jobs_.push_back(std::move(job));
  ++active_;
  return Describe(jobs_.back());
}

void ProcessingJobs::Launch(Job& job) {
  const fs::path log = job.output_dir / "process.log";
  std::vector<std::string> args = {options_.executable, "process", (job.output_dir / "recipe.json").string(),
                                   job.session_dir.string(), "--progress-file", (job.output_dir / "progress.json").string()};
  if (job.overwrite) args.push_back("--overwrite");
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);

  posix_spawn_file_actions_t files;
  posix_spawnattr_t attributes;
  posix_spawn_file_actions_init(&files);
  posix_spawnattr_init(&attributes);
  posix_spawn_file_actions_addopen(&files, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&files, STDOUT_FILENO, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&files, STDOUT_FILENO, STDERR_FILENO);
  // The ordinary policy whatever the loop runs under, default signals, none blocked.
  sigset_t none, defaults;
  sigemptyset(&none);
  sigemptyset(&defaults);
  for (int s : {SIGINT, SIGTERM, SIGPIPE, SIGCHLD, SIGHUP}) sigaddset(&defaults, s);
  sched_param priority{};
  priority.sched_priority = 0;
  posix_spawnattr_setschedpolicy(&attributes, SCHED_OTHER);
  posix_spawnattr_setschedparam(&attributes, &priority);
  posix_spawnattr_setsigmask(&attributes, &none);
  posix_spawnattr_setsigdefault(&attributes, &defaults);
  posix_spawnattr_setflags(&attributes, POSIX_SPAWN_SETSCHEDULER | POSIX_SPAWN_SETSIGMASK | POSIX_SPAWN_SETSIGDEF);
  pid_t pid = -1;
  const int error = posix_spawn(&pid, options_.executable.c_str(), &files, &attributes, argv.data(), environ);
  posix_spawn_file_actions_destroy(&files);
  posix_spawnattr_destroy(&attributes);
  if (error != 0) {
    job.state = "failed";
    job.reason = "cannot run " + options_.executable + ": " + std::strerror(error);
    return;
  }
  setpriority(PRIO_PROCESS, static_cast<id_t>(pid), kChildNice);
  job.pid = pid;
  job.state = "running";
}

void ProcessingJobs::Finish(Job& job, int wait_status) {
  job.pid = -1;
  if (WIFEXITED(wait_status)) {
    job.exit_status = WEXITSTATUS(wait_status);
    job.state = job.exit_status == 0 ? "done" : "failed";
    if (job.exit_status != 0) job.reason = "mocap-hub process exited with status " + std::to_string(job.exit_status) +
                                           " (its log says why)";
  } else {
    job.state = "failed";
    job.reason = std::string("mocap-hub process was ended by signal ") +
                 (WIFSIGNALED(wait_status) ? strsignal(WTERMSIG(wait_status)) : "?");
  }
}

void ProcessingJobs::Poll() {
  if (active_.load(std::memory_order_relaxed) == 0) return;
  const auto now = std::chrono::steady_clock::now();
  if (now < next_poll_) return;
  next_poll_ = now + std::chrono::milliseconds(50);
  std::lock_guard<std::mutex> lock(mutex_);
  bool running = false, changed = false;
  for (Job& job : jobs_) {
    if (job.state != "running") continue;
    int status = 0;
    const pid_t done = waitpid(job.pid, &status, WNOHANG);
    if (done == job.pid) {
      Finish(job, status);
      changed = true;
    } else if (done < 0 && errno != EINTR) {
      job.pid = -1;
      job.state = "failed";
      job.reason = std::string("lost track of its process: ") + std::strerror(errno);
      changed = true;
    } else {
      running = true;
    }
  }
  if (!running) {
    for (Job& job : jobs_) {
      if (job.state != "queued") continue;
      Launch(job);
      changed = true;
      if (job.state == "running") break;
    }
  }
  if (changed) Tidy();
}

void ProcessingJobs::Tidy() {
  const auto finished = [](const Job& j) { return j.state == "done" || j.state == "failed"; };
  // Keep the order: finished, running, queued; then the oldest finished beyond the history go.
  std::stable_partition(jobs_.begin(), jobs_.end(), finished);
  const size_t done = static_cast<size_t>(std::count_if(jobs_.begin(), jobs_.end(), finished));
  for (size_t extra = done > options_.history ? done - options_.history : 0; extra > 0; --extra) jobs_.pop_front();
  active_.store(jobs_.size() - std::min(done, options_.history), std::memory_order_relaxed);
}

nlohmann::json ProcessingJobs::Describe(const Job& job) const {
  nlohmann::json out = {{"id", job.id},
                        {"session", job.session},
                        {"recipe", job.recipe},
                        {"state", job.state},
                        {"reason", job.reason},
                        {"exit_status", job.exit_status >= 0 ? nlohmann::json(job.exit_status) : nlohmann::json()},
                        {"progress", job.state == "queued" ? nlohmann::json() : SmallJson(job.output_dir / "progress.json")},
                        {"log", job.state == "queued" ? nlohmann::json::array() : LogTail(job.output_dir / "process.log")},
                        {"outputs", nlohmann::json::array()}};
  if (job.state == "done") {
    const nlohmann::json report = SmallJson(job.output_dir / "process.json");
    if (report.is_object() && report.contains("outputs")) out["outputs"] = report["outputs"];
  }
  return out;
}

bool ProcessingJobs::Uses(const std::string& session) const {
  if (active_.load() == 0) return false;
  std::lock_guard<std::mutex> lock(mutex_);
  for (const Job& job : jobs_)
    if (job.session == session && (job.state == "queued" || job.state == "running")) return true;
  return false;
}

nlohmann::json ProcessingJobs::Jobs() const {
  std::lock_guard<std::mutex> lock(mutex_);
  nlohmann::json list = nlohmann::json::array();
  for (auto it = jobs_.rbegin(); it != jobs_.rend(); ++it) list.push_back(Describe(*it));
  return {{"jobs", list}};
}

}  // namespace mocap::service

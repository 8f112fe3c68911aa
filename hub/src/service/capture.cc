// Captures on command (see capture.h).
#include "service/capture.h"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/statvfs.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <system_error>

#include "io/live_points.h"
#include "service/api_error.h"
#include "service/calibration_files.h"
#include "util/log.h"

namespace mocap::service {
namespace fs = std::filesystem;
namespace {

constexpr uint64_t kFlushEveryNs = 50'000'000;
constexpr uint64_t kInfoEveryNs = 1'000'000'000;
constexpr char kReserveFile[] = ".reserve";
constexpr char kLockFile[] = ".serve.lock";

uint64_t Mb(double mb) { return static_cast<uint64_t>(mb * 1024.0 * 1024.0); }

std::string MbText(uint64_t bytes) {
  char text[32];
  std::snprintf(text, sizeof text, "%.1f MiB", static_cast<double>(bytes) / (1024.0 * 1024.0));
  return text;
}

// session.json's counts while capturing: replaced by a rename, but not synced to the disk (an
// fsync every second on the frame loop could stall it behind the raw log's writes); a killed
// process loses nothing, a power cut at most the last second's counts. Throws on failure.
void WriteInfoUnsynced(const SessionInfo& info, const std::string& dir) {
  const fs::path path = fs::path(dir) / "session.json";
  const fs::path temporary = fs::path(dir) / "session.json.tmp";
  {
    std::ofstream out(temporary, std::ios::trunc);
    out << info.ToJson().dump(2) << "\n";
    if (!out.flush()) throw std::runtime_error(temporary.string() + ": write failed");
  }
  std::error_code ec;
  fs::rename(temporary, path, ec);
  if (ec) throw std::runtime_error(path.string() + ": cannot replace: " + ec.message());
}

// ENOSPC and EDQUOT are the disk being full, whatever the write was.
std::string FailureReason(const SessionWriter& writer) {
  const int error = writer.failure_errno();
  if (error == ENOSPC || error == EDQUOT) return "disk full";
  return writer.failure();
}

const std::string kUnnamed;

}  // namespace

std::string CaptureDiskOptions::Check() const {
  const auto bad = [](const char* name, double value, const char* rule) {
    return std::string(name) + ": " + std::to_string(value) + " " + rule;
  };
  for (const auto& [name, value] : {std::pair<const char*, double>{"start_free_mb", start_free_mb},
                                    {"warn_free_mb", warn_free_mb},
                                    {"stop_free_mb", stop_free_mb}})
    if (!(value >= 0.0 && value <= 1e9)) return bad(name, value, "must be 0..1e9");
  if (stop_free_mb > start_free_mb) return bad("stop_free_mb", stop_free_mb, "must be at most start_free_mb");
  if (!(check_every_s > 0.0 && check_every_s <= 60.0)) return bad("check_every_s", check_every_s, "must be in (0, 60]");
  if (!(reserve_kb >= 0.0 && reserve_kb <= 65536.0)) return bad("reserve_kb", reserve_kb, "must be 0..65536");
  return "";
}

uint64_t FreeBytes(const std::string& path) {
  struct statvfs fs_info {};
  if (::statvfs(path.c_str(), &fs_info) != 0)
    throw std::runtime_error(path + ": cannot read the free space: " + std::strerror(errno));
  return static_cast<uint64_t>(fs_info.f_bavail) * fs_info.f_frsize;
}

Captures::Captures(std::string sessions_dir, std::string calibration_file, SessionInfo base, CaptureDiskOptions disk,
                   FreeBytesFunction free_bytes)
    : disk_(disk),
      free_bytes_(std::move(free_bytes)),
      dir_(std::move(sessions_dir)),
      calibration_file_(std::move(calibration_file)),
      base_(std::move(base)) {
  if (const std::string error = disk_.Check(); !error.empty()) throw std::invalid_argument(error);
}

Captures::~Captures() {
  if (lock_fd_ >= 0) ::close(lock_fd_);
  if (direct_lock_fd_ >= 0) ::close(direct_lock_fd_);
}

void Captures::Lock() {
  if (dir_.empty()) return;  // record's hub: no sessions directory
  std::error_code ec;
  fs::create_directories(dir_, ec);
  if (ec) throw std::runtime_error(dir_ + ": cannot create: " + ec.message());
  lock_fd_ = LockDirectory(dir_);
}

int Captures::LockDirectory(const std::string& dir) {
  const std::string path = (fs::path(dir) / kLockFile).string();
  const int fd = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd < 0) throw std::runtime_error(path + ": cannot open: " + std::strerror(errno));
  if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
    const int error = errno;
    char holder[32] = {};
    const ssize_t n = ::pread(fd, holder, sizeof holder - 1, 0);
    ::close(fd);
    if (error == EWOULDBLOCK)
      throw std::runtime_error("sessions directory " + dir + " is in use by another serve or record (pid " +
                               std::string(holder, n > 0 ? static_cast<size_t>(n) : 0) +
                               "): one at a time; stop it or give --sessions-dir (record: -o) another one");
    throw std::runtime_error(path + ": cannot lock: " + std::strerror(error));
  }
  const std::string pid = std::to_string(::getpid());
  if (::ftruncate(fd, 0) != 0 || ::pwrite(fd, pid.data(), pid.size(), 0) != static_cast<ssize_t>(pid.size()))
    log::Warn("{}: cannot write the pid: {}", path, std::strerror(errno));
  return fd;
}

std::vector<std::string> Captures::RecoverInterrupted() {
  std::vector<std::string> names;
  std::error_code ec;
  if (!fs::is_directory(dir_, ec)) return names;
  for (const fs::directory_entry& entry : fs::directory_iterator(dir_, ec)) {
    if (!entry.is_directory() || !fs::exists(entry.path() / "session.json")) continue;
    try {
      fs::remove(entry.path() / kReserveFile, ec);
      SessionInfo info = LoadSessionInfo(entry.path().string());
      if (info.extra.value("capture_state", "") != "capturing") continue;
      info.extra["capture_state"] = "interrupted";
      SaveSessionInfo(info, entry.path().string());
      names.push_back(entry.path().filename().string());
    } catch (const std::exception& e) {
      log::Warn("{}: {}", entry.path().string(), e.what());
    }
  }
  return names;
}

void Captures::Start(const std::string& name, const IngestStats& stats, uint64_t now_ns) {
  if (!ValidSessionName(name))
    throw ApiError(400, "session name '" + name + "': use 1-64 letters, digits, '.', '-' or '_', not starting with '.'");
  if (writer_) throw ApiError(409, "capture '" + name_ + "' is running; stop it first");
  if (dir_.empty()) throw ApiError(409, "this hub has no sessions directory");
  const fs::path path = fs::path(dir_) / name;
  std::error_code ec;
  if (fs::exists(path, ec)) throw ApiError(409, "session '" + name + "' exists already in " + dir_);
  Begin(path, name, "serve", stats, now_ns);
}

void Captures::StartDirect(DirectCapture capture, const IngestStats& stats, uint64_t now_ns) {
  if (capture.dir.empty()) throw ApiError(400, "dir: \"\" must name the session's directory");
  if (writer_) throw ApiError(409, "capture '" + name_ + "' is running; stop it first");
  const fs::path path = fs::path(capture.dir).lexically_normal();
  const fs::path parent = path.has_filename() ? path.parent_path() : path.parent_path().parent_path();
  std::error_code ec;
  // A serve's sessions directory is locked as that serve would, so neither relabels the other's session.
  if (!parent.empty() && fs::exists(parent / kLockFile, ec)) {
    try {
      direct_lock_fd_ = LockDirectory(parent.string());
    } catch (const std::exception& e) {
      throw ApiError(409, e.what());
    }
  }
  fs::create_directories(path, ec);  // SessionWriter::Create says why, if this failed
  try {
    Begin(path, path.filename().empty() ? path.parent_path().filename().string() : path.filename().string(),
          capture.source, stats, now_ns);
  } catch (const ApiError&) {
    if (direct_lock_fd_ >= 0) ::close(direct_lock_fd_);
    direct_lock_fd_ = -1;
    throw;
  }
  direct_ = std::move(capture);
}

void Captures::Begin(const fs::path& path, const std::string& name, const std::string& source,
                     const IngestStats& stats, uint64_t now_ns) {
  const std::string disk = dir_.empty() ? path.string() : dir_;
  std::error_code ec;
  try {
    free_ = free_bytes_(disk);
  } catch (const std::exception& e) {
    throw ApiError(500, e.what());
  }
  if (free_ < Mb(disk_.start_free_mb))
    throw ApiError(507, "sessions disk " + disk + ": " + MbText(free_) + " free, a capture needs at least " +
                            MbText(Mb(disk_.start_free_mb)) + " (start_free_mb)");
  SessionInfo info = base_;
  info.source = source;
  info.extra["capture_state"] = "capturing";
  info.extra["started_ns"] = now_ns;
  auto writer = std::make_unique<SessionWriter>();
  try {
    writer->Create(path.string(), info);
    fs::copy_file(calibration_file_, path / info.calibration, fs::copy_options::overwrite_existing);
    std::ofstream reserve(path / kReserveFile, std::ios::binary);
    const std::string block(4096, '\0');
    for (double kb = 0.0; kb < disk_.reserve_kb; kb += 4.0) reserve << block;
    if (!reserve.flush()) throw std::runtime_error((path / kReserveFile).string() + ": cannot write");
  } catch (const std::exception& e) {
    fs::remove(path / kReserveFile, ec);
    throw ApiError(500, e.what());
  }
  writer->KeepFailures();
  live_ = std::ofstream(path / "live_points.tsv");
  if (!live_) throw ApiError(500, (path / "live_points.tsv").string() + ": cannot create");
  live_ << LivePointsHeader(base_.rate_hz);
  writer_ = std::move(writer);
  name_ = name;
  path_ = path.string();
  started_ns_ = now_ns;
  last_flush_ns_ = now_ns;
  last_check_ns_ = now_ns;
  last_info_ns_ = now_ns;
  frame_sets_ = 0;
  at_start_ = stats;
  direct_ = DirectCapture{};
  last_datagram_ns_ = 0;
  limit_reached_ = false;
}

SessionWriter* Captures::WriterFor(uint64_t receive_time_ns) {
  if (!writer_) return nullptr;
  last_datagram_ns_ = std::max(last_datagram_ns_, receive_time_ns);
  if (direct_.end_receive_ns && receive_time_ns >= direct_.end_receive_ns) {
    limit_reached_ = true;
    return nullptr;
  }
  return writer_.get();
}

void Captures::UpdateInfo(const IngestStats& stats) {
  SessionInfo& info = writer_->info();
  info.frame_sets = frame_sets_;
  const IngestTotals now = stats.Totals(), then = at_start_.Totals();
  info.camera_frames = now.frames - then.frames;
  info.dropped_camera_frames = now.dropped_frames - then.dropped_frames;
  info.extra["off_clock_frames"] = now.off_clock_frames - then.off_clock_frames;
  info.extra["rescaled_frames"] = now.rescaled_frames - then.rescaled_frames;
  info.extra["wrong_size_frames"] = now.wrong_size_frames - then.wrong_size_frames;
  info.extra["malformed_datagrams"] = stats.malformed - at_start_.malformed;
}

void Captures::RemoveReserve() {
  std::error_code ec;
  fs::remove(fs::path(path_) / kReserveFile, ec);
}

void Captures::Ended() {
  writer_.reset();
  limit_reached_ = false;
  direct_ = DirectCapture{};
  if (direct_lock_fd_ >= 0) ::close(direct_lock_fd_);
  direct_lock_fd_ = -1;
}

nlohmann::json Captures::Fail(const std::string& reason, const IngestStats& stats, uint64_t now_ns) {
  UpdateInfo(stats);
  SessionInfo& info = writer_->info();
  info.extra["capture_state"] = "failed";
  info.extra["failure"] = reason;
  info.extra["stopped_ns"] = now_ns;
  nlohmann::json summary = Current(now_ns);
  summary["state"] = "failed";
  summary["reason"] = reason;
  log::Error("capture {} failed: {} ({} frame sets kept; the service goes on)", name_, reason, frame_sets_);
  live_.close();
  // The reserve makes room for session.json on a disk the capture filled.
  RemoveReserve();
  try {
    writer_->Finish();
  } catch (const std::exception& e) {
    log::Error("capture {}: {}", name_, e.what());
    try {
      SaveSessionInfo(info, writer_->dir());
    } catch (const std::exception& again) {
      log::Error("capture {}: session.json not updated: {}", name_, again.what());
    }
  }
  Ended();
  last_ = summary;
  return summary;
}

nlohmann::json Captures::Stop(const IngestStats& stats, uint64_t now_ns) {
  if (!writer_) throw ApiError(409, "no capture is running");
  writer_->Flush();
  if (!writer_->failure().empty()) {
    const nlohmann::json summary = Fail(FailureReason(*writer_), stats, now_ns);
    throw ApiError(507, "capture '" + summary.value("name", "") + "' failed: " + summary.value("reason", ""));
  }
  UpdateInfo(stats);
  SessionInfo& info = writer_->info();
  info.extra["capture_state"] = "complete";
  info.extra["stopped_ns"] = now_ns;
  nlohmann::json summary = Current(now_ns);
  summary["state"] = "complete";
  live_.close();
  RemoveReserve();
  try {
    writer_->Finish();
  } catch (const std::exception& e) {
    Ended();
    throw ApiError(500, e.what());
  }
  Ended();
  last_ = summary;
  return summary;
}

bool Captures::CheckSpace(uint64_t now_ns) {
  last_check_ns_ = now_ns;
  try {
    free_ = free_bytes_(DiskPath());
  } catch (const std::exception& e) {
    log::Warn("{}", e.what());
    return true;
  }
  if (free_ < Mb(disk_.stop_free_mb)) return false;
  const bool low = free_ < Mb(disk_.warn_free_mb);
  if (low && !warned_)
    log::Warn("sessions disk {}: {} free (warn_free_mb {}); a capture stops below {}", DiskPath(), MbText(free_),
              disk_.warn_free_mb, MbText(Mb(disk_.stop_free_mb)));
  warned_ = low;
  return true;
}

std::string Captures::ReasonFor(const std::string& error) {
  // A write that failed on a disk with less than a block or two left failed for that.
  try {
    free_ = free_bytes_(DiskPath());
  } catch (const std::exception&) {
    return error;
  }
  return free_ < Mb(disk_.stop_free_mb) + 65536 ? "disk full" : error;
}

nlohmann::json Captures::Tick(const IngestStats& stats, uint64_t now_ns) {
  const bool check = now_ns >= last_check_ns_ + static_cast<uint64_t>(disk_.check_every_s * 1e9);
  if (!writer_) {
    if (check && !dir_.empty()) CheckSpace(now_ns);
    return nullptr;
  }
  if ((direct_.end_receive_ns && now_ns >= direct_.end_receive_ns) ||
      (direct_.idle_ns && last_datagram_ns_ && now_ns > last_datagram_ns_ + direct_.idle_ns))
    limit_reached_ = true;
  if (now_ns >= last_flush_ns_ + kFlushEveryNs) {
    writer_->Flush();
    live_.flush();
    last_flush_ns_ = now_ns;
  }
  if (!writer_->failure().empty()) {
    const std::string reason = FailureReason(*writer_);
    return Fail(reason == "disk full" ? reason : ReasonFor(reason), stats, now_ns);
  }
  if (!live_) return Fail(ReasonFor("live_points.tsv: write failed"), stats, now_ns);
  if (check && !CheckSpace(now_ns)) return Fail("disk full", stats, now_ns);
  if (now_ns >= last_info_ns_ + kInfoEveryNs) {
    last_info_ns_ = now_ns;
    UpdateInfo(stats);
    try {
      WriteInfoUnsynced(writer_->info(), writer_->dir());
    } catch (const std::exception& e) {
      return Fail(ReasonFor(e.what()), stats, now_ns);
    }
  }
  return nullptr;
}

nlohmann::json Captures::Disk() const {
  return {{"free_bytes", free_},
          {"low", free_ < Mb(disk_.warn_free_mb)},
          {"warn_free_mb", disk_.warn_free_mb},
          {"stop_free_mb", disk_.stop_free_mb}};
}

void Captures::AddPublished(const pipeline::LiveFrame& frame, const FrameSet& set) {
  if (direct_.max_frame_sets && frame_sets_ >= direct_.max_frame_sets) return;
  if (direct_.end_receive_ns && frame.last_receive_ns >= direct_.end_receive_ns) return;
  ++frame_sets_;
  if (direct_.max_frame_sets && frame_sets_ == direct_.max_frame_sets) limit_reached_ = true;
  if (direct_.on_frame) direct_.on_frame(set, frame);
  for (const pipeline::LivePoint& p : frame.points) {
    const long long id = p.id ? static_cast<long long>(p.id) : -1;
    const std::string& name = p.label >= 0 && frame.label_names ? (*frame.label_names)[p.label] : kUnnamed;
    live_ << LivePointLine(frame.frame_number, p.position.x(), p.position.y(), p.position.z(), id, p.provisional(),
                           p.views, p.rms_px, name);
  }
}

nlohmann::json Captures::Current(uint64_t now_ns) const {
  if (!writer_) return nullptr;
  return {{"name", name_},
          {"path", path_},
          {"state", "capturing"},
          {"frame_sets", frame_sets_},
          {"seconds", static_cast<double>(now_ns - started_ns_) * 1e-9}};
}

nlohmann::json Captures::Summary(const fs::path& path) const {
  nlohmann::json item = {{"name", path.filename().string()}, {"path", path.string()}};
  try {
    const SessionInfo info = LoadSessionInfo(path.string());
    const bool current = writer_ && path.filename() == name_;
    item["state"] = current ? "capturing" : info.extra.value("capture_state", "complete");
    item["source"] = info.source;
    item["frame_sets"] = current ? frame_sets_ : info.frame_sets;
    item["cameras"] = info.camera_ids.size();
    item["rate_hz"] = info.rate_hz;
    std::ifstream notes(path / kNotesFile, std::ios::binary);
    std::string text(kMaxNotesBytes, '\0');
    notes.read(text.data(), static_cast<std::streamsize>(text.size()));
    text.resize(static_cast<size_t>(notes.gcount()));
    if (!text.empty()) item["notes"] = text;
  } catch (const std::exception& e) {
    item["state"] = "unreadable";
    item["error"] = e.what();
  }
  return item;
}

nlohmann::json Captures::List() const {
  nlohmann::json list = nlohmann::json::array();
  std::error_code ec;
  if (!fs::is_directory(dir_, ec)) return list;
  std::vector<fs::path> dirs;
  for (const fs::directory_entry& entry : fs::directory_iterator(dir_, ec))
    if (entry.is_directory() && fs::exists(entry.path() / "session.json")) dirs.push_back(entry.path());
  std::sort(dirs.begin(), dirs.end());
  for (const fs::path& path : dirs) list.push_back(Summary(path));
  return list;
}

fs::path Captures::SessionPath(const std::string& name) const {
  std::error_code ec;
  const fs::path path = fs::path(dir_) / name;
  if (dir_.empty() || !ValidSessionName(name) || !fs::is_directory(fs::symlink_status(path, ec)) ||
      !fs::exists(path / "session.json", ec))
    throw ApiError(404, "no session '" + name + "'");
  return path;
}

// [{"name", "bytes"}] of the regular files with plain names directly in dir (links left out).
nlohmann::json Captures::FilesJson(const fs::path& dir) {
  std::vector<std::pair<std::string, uintmax_t>> files;
  std::error_code ec;
  for (const fs::directory_entry& entry : fs::directory_iterator(dir, ec)) {
    const std::string file = entry.path().filename().string();
    std::error_code size_ec;
    if (!ValidSessionName(file) || !fs::is_regular_file(entry.symlink_status(size_ec))) continue;
    const uintmax_t bytes = fs::file_size(entry.path(), size_ec);
    if (!size_ec) files.emplace_back(file, bytes);
  }
  std::sort(files.begin(), files.end());
  nlohmann::json list = nlohmann::json::array();
  for (const auto& [file, bytes] : files) list.push_back({{"name", file}, {"bytes", bytes}});
  return list;
}

nlohmann::json Captures::Describe(const std::string& name) const {
  const fs::path path = SessionPath(name);
  std::error_code ec;
  nlohmann::json item = Summary(path);
  item["files"] = FilesJson(path);
  // Results of processing recipes (processing_jobs.h), one directory per recipe.
  item["processed"] = nlohmann::json::array();
  std::vector<std::string> recipes;
  for (const fs::directory_entry& entry : fs::directory_iterator(path / "processed", ec)) {
    const std::string recipe = entry.path().filename().string();
    std::error_code kind_ec;
    if (ValidSessionName(recipe) && fs::is_directory(entry.symlink_status(kind_ec))) recipes.push_back(recipe);
  }
  std::sort(recipes.begin(), recipes.end());
  for (const std::string& recipe : recipes)
    item["processed"].push_back({{"recipe", recipe}, {"files", FilesJson(path / "processed" / recipe)}});
  return item;
}

std::string Captures::ProcessedDirPath(const std::string& name, const std::string& recipe) const {
  const fs::path dir = SessionPath(name) / "processed" / recipe;
  std::error_code ec;
  if (!ValidSessionName(recipe) || !fs::is_directory(fs::symlink_status(dir, ec)))
    throw ApiError(404, "session '" + name + "' has no results of recipe '" + recipe + "'");
  return dir.string();
}

std::string Captures::ProcessedFilePath(const std::string& name, const std::string& recipe,
                                        const std::string& file) const {
  const fs::path dir = ProcessedDirPath(name, recipe);
  std::error_code ec;
  const fs::path path = dir / file;
  if (!ValidSessionName(file) || !fs::is_regular_file(fs::symlink_status(path, ec)))
    throw ApiError(404, "session '" + name + "' has no file '" + file + "' in its results of recipe '" + recipe + "'");
  return path.string();
}

std::string Captures::FilePath(const std::string& name, const std::string& file) const {
  const fs::path path = SessionPath(name) / file;
  std::error_code ec;
  if (!ValidSessionName(file) || !fs::is_regular_file(fs::symlink_status(path, ec)))
    throw ApiError(404, "session '" + name + "' has no file '" + file + "'");
  return path.string();
}

fs::path Captures::IdleSessionPath(const std::string& name) const {
  fs::path path = SessionPath(name);
  if (writer_ && name == name_) throw ApiError(409, "session '" + name + "' is being captured; stop the capture first");
  return path;
}

nlohmann::json Captures::Delete(const std::string& name, uint64_t now_ns) {
  const fs::path path = IdleSessionPath(name);
  const fs::path trash = fs::path(dir_) / ".deleted";
  std::error_code ec;
  fs::create_directories(trash, ec);
  if (ec) throw ApiError(500, trash.string() + ": " + ec.message());
  const fs::path to = DatedCopyName((trash / name).string(), now_ns);
  fs::rename(path, to, ec);
  if (ec) throw ApiError(500, "session '" + name + "' not deleted: " + ec.message());
  log::Info("session {} deleted: moved to {}", name, to.string());
  return {{"name", name}, {"moved_to", to.string()}};
}

nlohmann::json Captures::Rename(const std::string& name, const std::string& new_name) {
  const fs::path path = IdleSessionPath(name);
  if (!ValidSessionName(new_name))
    throw ApiError(400, "'" + new_name + "' cannot name a session: 1-64 letters, digits, '.', '-', '_', not starting with '.'");
  const fs::path to = fs::path(dir_) / new_name;
  std::error_code ec;
  if (fs::exists(fs::symlink_status(to, ec))) throw ApiError(409, "a session '" + new_name + "' exists already");
  fs::rename(path, to, ec);
  if (ec) throw ApiError(500, "session '" + name + "' not renamed: " + ec.message());
  log::Info("session {} renamed {}", name, new_name);
  return Summary(to);
}

nlohmann::json Captures::SetNotes(const std::string& name, const std::string& notes) {
  const fs::path path = IdleSessionPath(name);
  if (notes.size() > kMaxNotesBytes)
    throw ApiError(400, "notes of " + std::to_string(notes.size()) + " bytes: at most " + std::to_string(kMaxNotesBytes));
  const fs::path file = path / kNotesFile;
  std::error_code ec;
  if (notes.empty()) {
    fs::remove(file, ec);
    if (ec) throw ApiError(500, file.string() + ": " + ec.message());
    return Summary(path);
  }
  // Written beside and renamed over, so a failed write leaves the old notes whole.
  const fs::path temporary = path / ".notes.txt.new";
  {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    out << notes;
    out.close();
    if (!out) {
      fs::remove(temporary, ec);
      throw ApiError(500, file.string() + ": cannot write the notes");
    }
  }
  fs::rename(temporary, file, ec);
  if (ec) throw ApiError(500, file.string() + ": " + ec.message());
  return Summary(path);
}

}  // namespace mocap::service

// Captures on command (see capture.h).
#include "service/capture.h"

#include <algorithm>
#include <filesystem>
#include <system_error>

#include "io/live_points.h"
#include "service/api_error.h"
#include "util/log.h"

namespace mocap::service {
namespace fs = std::filesystem;
namespace {

constexpr uint64_t kFlushEveryNs = 50'000'000;
const std::string kUnnamed;

}  // namespace

bool ValidSessionName(const std::string& name) {
  if (name.empty() || name.size() > 64 || name[0] == '.') return false;
  for (char c : name) {
    const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '.' ||
                    c == '-' || c == '_';
    if (!ok) return false;
  }
  return true;
}

Captures::Captures(std::string sessions_dir, std::string calibration_file, SessionInfo base)
    : dir_(std::move(sessions_dir)), calibration_file_(std::move(calibration_file)), base_(std::move(base)) {}

std::vector<std::string> Captures::RecoverInterrupted() {
  std::vector<std::string> names;
  std::error_code ec;
  if (!fs::is_directory(dir_, ec)) return names;
  for (const fs::directory_entry& entry : fs::directory_iterator(dir_, ec)) {
    if (!entry.is_directory() || !fs::exists(entry.path() / "session.json")) continue;
    try {
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
  const fs::path path = fs::path(dir_) / name;
  std::error_code ec;
  if (fs::exists(path, ec)) throw ApiError(409, "session '" + name + "' exists already in " + dir_);
  SessionInfo info = base_;
  info.source = "serve";
  info.extra["capture_state"] = "capturing";
  info.extra["started_ns"] = now_ns;
  auto writer = std::make_unique<SessionWriter>();
  try {
    writer->Create(path.string(), info);
    fs::copy_file(calibration_file_, path / info.calibration, fs::copy_options::overwrite_existing);
  } catch (const std::exception& e) {
    throw ApiError(500, e.what());
  }
  live_ = std::ofstream(path / "live_points.tsv");
  if (!live_) throw ApiError(500, (path / "live_points.tsv").string() + ": cannot create");
  live_ << LivePointsHeader(base_.rate_hz);
  writer_ = std::move(writer);
  name_ = name;
  started_ns_ = now_ns;
  last_flush_ns_ = now_ns;
  frame_sets_ = 0;
  at_start_ = stats;
}

nlohmann::json Captures::Stop(const IngestStats& stats, uint64_t now_ns) {
  if (!writer_) throw ApiError(409, "no capture is running");
  SessionInfo& info = writer_->info();
  info.frame_sets = frame_sets_;
  const IngestTotals now = stats.Totals(), then = at_start_.Totals();
  info.camera_frames = now.frames - then.frames;
  info.dropped_camera_frames = now.dropped_frames - then.dropped_frames;
  info.extra["off_clock_frames"] = now.off_clock_frames - then.off_clock_frames;
  info.extra["rescaled_frames"] = now.rescaled_frames - then.rescaled_frames;
  info.extra["wrong_size_frames"] = now.wrong_size_frames - then.wrong_size_frames;
  info.extra["capture_state"] = "complete";
  info.extra["stopped_ns"] = now_ns;
  info.extra["malformed_datagrams"] = stats.malformed - at_start_.malformed;
  nlohmann::json summary = Current(now_ns);
  summary["state"] = "complete";
  live_.close();
  try {
    writer_->Finish();
  } catch (const std::exception& e) {
    writer_.reset();
    throw ApiError(500, e.what());
  }
  writer_.reset();
  return summary;
}

void Captures::MaybeFlush(uint64_t now_ns) {
  if (!writer_ || now_ns < last_flush_ns_ + kFlushEveryNs) return;
  writer_->Flush();
  live_.flush();
  last_flush_ns_ = now_ns;
}

void Captures::AddPublished(const LiveFrame& frame) {
  ++frame_sets_;
  for (const LivePoint& p : frame.points) {
    const long long id = p.provisional() ? (p.provisional_track ? static_cast<long long>(p.provisional_track) : -1)
                                         : static_cast<long long>(p.marker);
    const std::string& name = p.label >= 0 && frame.label_names ? (*frame.label_names)[p.label] : kUnnamed;
    live_ << LivePointLine(frame.frame_number, p.position.x(), p.position.y(), p.position.z(), id, p.provisional(),
                           p.views, p.rms_px, name);
  }
}

nlohmann::json Captures::Current(uint64_t now_ns) const {
  if (!writer_) return nullptr;
  return {{"name", name_},
          {"path", (fs::path(dir_) / name_).string()},
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
  if (!ValidSessionName(name) || !fs::is_directory(fs::symlink_status(path, ec)) ||
      !fs::exists(path / "session.json", ec))
    throw ApiError(404, "no session '" + name + "'");
  return path;
}

nlohmann::json Captures::Describe(const std::string& name) const {
  const fs::path path = SessionPath(name);
  std::vector<std::pair<std::string, uintmax_t>> files;
  std::error_code ec;
  for (const fs::directory_entry& entry : fs::directory_iterator(path, ec)) {
    const std::string file = entry.path().filename().string();
    std::error_code size_ec;
    if (!ValidSessionName(file) || !fs::is_regular_file(entry.symlink_status(size_ec))) continue;
    const uintmax_t bytes = fs::file_size(entry.path(), size_ec);
    if (!size_ec) files.emplace_back(file, bytes);
  }
  std::sort(files.begin(), files.end());
  nlohmann::json item = Summary(path);
  item["files"] = nlohmann::json::array();
  for (const auto& [file, bytes] : files) item["files"].push_back({{"name", file}, {"bytes", bytes}});
  return item;
}

std::string Captures::FilePath(const std::string& name, const std::string& file) const {
  const fs::path path = SessionPath(name) / file;
  std::error_code ec;
  if (!ValidSessionName(file) || !fs::is_regular_file(fs::symlink_status(path, ec)))
    throw ApiError(404, "session '" + name + "' has no file '" + file + "'");
  return path.string();
}

}  // namespace mocap::service

// Session directory reading and writing (see session.h).
#include "ingest/session.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <stdexcept>

#include "ingest/frame_codec.h"
#include "wire/packet.h"
#include "util/json_file.h"

namespace mocap {
namespace fs = std::filesystem;

namespace {

// A JSON integer from 0 to T's maximum. nlohmann's get<unsigned>() converts a float or a negative
// number too: a float beyond the type's range ("epoch_ns": 1e48) is undefined behaviour, a
// negative one wraps to a huge count, so neither reaches it.
template <typename T>
T UnsignedValue(const nlohmann::json& value, const std::string& name) {
  if (!value.is_number_unsigned() || value.get<uint64_t>() > std::numeric_limits<T>::max())
    throw std::runtime_error(name + " must be an integer from 0 to " + std::to_string(std::numeric_limits<T>::max()) +
                             ", not " + value.dump());
  return static_cast<T>(value.get<uint64_t>());
}

uint64_t OptionalCount(const nlohmann::json& j, const char* name) {
  return j.contains(name) ? UnsignedValue<uint64_t>(j[name], name) : 0;
}

}  // namespace

nlohmann::json SessionInfo::ToJson() const {
  nlohmann::json j = extra;
  j["format"] = "mocap-session";
  j["version"] = 1;
  j["rate_hz"] = rate_hz;
  j["epoch_ns"] = epoch_ns;
  j["free_run"] = free_run;
  j["cameras"] = camera_ids;
  j["frame_sets"] = frame_sets;
  j["camera_frames"] = camera_frames;
  j["dropped_camera_frames"] = dropped_camera_frames;
  j["calibration"] = calibration;
  j["log"] = log;
  j["source"] = source;
  return j;
}

SessionInfo SessionInfo::FromJson(const nlohmann::json& j) {
  // Compared as JSON values: a field of another type is a wrong value, not a type error.
  if (!j.is_object() || !j.contains("format") || j["format"] != "mocap-session")
    throw std::runtime_error("not a mocap session description");
  if (!j.contains("version") || j["version"] != 1)
    throw std::runtime_error("unsupported session version " + j.value("version", nlohmann::json()).dump());
  SessionInfo info;
  try {
    info.rate_hz = j.at("rate_hz").get<double>();
    info.epoch_ns = OptionalCount(j, "epoch_ns");
    info.free_run = j.value("free_run", false);
    const nlohmann::json& cameras = j.at("cameras");
    if (!cameras.is_array()) throw std::runtime_error("cameras must be a list of camera ids");
    for (const nlohmann::json& id : cameras) info.camera_ids.push_back(UnsignedValue<uint32_t>(id, "a camera id"));
    info.frame_sets = OptionalCount(j, "frame_sets");
    info.camera_frames = OptionalCount(j, "camera_frames");
    info.dropped_camera_frames = OptionalCount(j, "dropped_camera_frames");
    info.calibration = j.value("calibration", std::string("calibration.json"));
    info.log = j.value("log", std::string("raw.mlog"));
    info.source = j.value("source", std::string());
  } catch (const nlohmann::json::exception& e) {
    throw std::runtime_error(std::string("bad session description: ") + e.what());
  }
  if (!(info.rate_hz > 0.0 && info.rate_hz < 100000.0))
    throw std::runtime_error("session rate_hz must be positive");
  if (info.log.empty() || info.log.find('/') != std::string::npos)
    throw std::runtime_error("session log must be a file name inside the session directory");
  info.extra = j;
  for (const char* known : {"format", "version", "rate_hz", "epoch_ns", "free_run", "cameras", "frame_sets",
                            "camera_frames", "dropped_camera_frames", "calibration", "log", "source"})
    info.extra.erase(known);
  return info;
}

SessionInfo LoadSessionInfo(const std::string& dir) {
  const std::string path = (fs::path(dir) / "session.json").string();
  if (!fs::exists(path)) throw std::runtime_error(path + ": cannot open (is " + dir + " a session directory?)");
  const nlohmann::json document = ReadJsonFile(path);
  try {
    return SessionInfo::FromJson(document);
  } catch (const std::runtime_error& e) {
    throw std::runtime_error(path + ": " + e.what());
  }
}

void SaveSessionInfo(const SessionInfo& info, const std::string& dir) {
  WriteJsonFile(info.ToJson(), (fs::path(dir) / "session.json").string());
}

void SessionWriter::Create(const std::string& dir, const SessionInfo& info, Existing existing) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw std::runtime_error(dir + ": cannot create session directory: " + ec.message());
  const std::string log = (fs::path(dir) / info.log).string();
  if (existing == Existing::kRefuse && fs::exists(log, ec))
    throw std::runtime_error(dir + ": holds a recorded session already (" + info.log +
                             "); not overwriting it: choose another directory or remove it");
  dir_ = dir;
  info_ = info;
  log_.Open(log, existing == Existing::kRefuse);
  // session.json exists from the start so that a crashed recording is still a readable session.
  SaveSessionInfo(info_, dir_);
}

void SessionWriter::Write(const CameraFrame& frame) {
  if (any_frame_ && frame.frame_number != last_frame_number_) log_.Flush();
  if (!any_frame_ || frame.frame_number != last_frame_number_) ++info_.frame_sets;
  any_frame_ = true;
  last_frame_number_ = frame.frame_number;
  for (const auto& datagram : EncodeCameraFrame(frame))
    log_.Append(datagram.data(), datagram.size(), frame.receive_time_ns);
  ++info_.camera_frames;
}

template <typename Operation>
void SessionWriter::Guarded(Operation operation) {
  if (!keep_failures_) {
    operation();
    return;
  }
  if (!failure_.empty()) return;
  try {
    operation();
  } catch (const std::runtime_error& e) {
    failure_ = e.what();
    failure_errno_ = log_.error_number();
  }
}

void SessionWriter::AppendDatagram(const uint8_t* data, size_t size, uint64_t receive_time_ns) {
  Guarded([&] { log_.Append(data, size, receive_time_ns); });
}

void SessionWriter::Flush() {
  Guarded([&] { log_.Flush(); });
}

void SessionWriter::Finish() {
  log_.Close();
  SaveSessionInfo(info_, dir_);
}

uint64_t MaxFrameGap(const SessionInfo& info) {
  // A session without a rate still gets a finite bound (a pause at 1 kHz).
  const double rate = info.rate_hz > 0.0 ? info.rate_hz : 1000.0;
  return static_cast<uint64_t>(std::ceil(rate * kMaxPauseSeconds));
}

void SessionReader::Open(const std::string& dir) {
  dir_ = dir;
  info_ = LoadSessionInfo(dir);
  max_gap_ = MaxFrameGap(info_);
  log_.Open((fs::path(dir) / info_.log).string());
}

// Written without sums that could wrap for frame numbers near UINT64_MAX.
bool SessionReader::Plausible(uint64_t frame_number, uint64_t receive_time_ns) const {
  if (accepted_any_) return frame_number <= newest_ || frame_number - newest_ <= max_gap_;
  if (!(info_.rate_hz > 0.0) || receive_time_ns <= info_.epoch_ns) return frame_number <= max_gap_;
  const double implied = static_cast<double>(receive_time_ns - info_.epoch_ns) * 1e-9 * info_.rate_hz;
  return static_cast<double>(frame_number) <= implied + static_cast<double>(max_gap_);
}

bool SessionReader::ReadMore() {
  LogRecord record;
  while (log_.Next(&record)) {
    ++stats_.datagrams;
    stats_.damaged_log_stretches = log_.damaged_stretches();
    stats_.skipped_log_bytes = log_.skipped_bytes();
    const wire::DecodeResult decoded = wire::Decode(record.payload.data(), record.payload.size());
    if (!decoded.ok) {
      if (stats_.malformed++ == 0) first_malformed_reason_ = decoded.reason;
      continue;
    }
    if (!decoded.packet.has_marker_frame()) {
      ++stats_.other_packets;
      continue;
    }
    v1::MarkerFrame whole;
    switch (assembler_.Add(decoded.packet.marker_frame(), &whole)) {
      case wire::ChunkAssembler::Outcome::kDuplicate: ++stats_.duplicate_chunks; continue;
      case wire::ChunkAssembler::Outcome::kInconsistent: ++stats_.inconsistent_chunks; continue;
      case wire::ChunkAssembler::Outcome::kOverflow: ++stats_.incomplete_frames; continue;
      case wire::ChunkAssembler::Outcome::kIncomplete: continue;
      case wire::ChunkAssembler::Outcome::kComplete: break;
    }
    CameraFrame frame = FromMarkerFrame(whole, record.receive_time_ns);
    if (!Plausible(frame.frame_number, record.receive_time_ns)) {
      ++stats_.implausible_frames;
      continue;
    }
    switch (image_sizes_.Apply(&frame)) {
      case ImageSizeVerdict::kRefused: ++stats_.wrong_size_frames; continue;
      case ImageSizeVerdict::kRescaled: ++stats_.rescaled_frames; break;
      case ImageSizeVerdict::kSame: break;
    }
    if (emitted_any_ && frame.frame_number <= last_emitted_) {
      ++stats_.late_frames;
      continue;
    }
    FrameSet& set = pending_[frame.frame_number];
    set.frame_number = frame.frame_number;
    bool duplicate = false;
    for (const CameraFrame& existing : set.cameras) duplicate |= existing.camera_id == frame.camera_id;
    if (duplicate) {
      ++stats_.duplicate_frames;
      continue;
    }
    if (!accepted_any_ || frame.frame_number > newest_) newest_ = frame.frame_number;
    accepted_any_ = true;
    set.cameras.push_back(std::move(frame));
    if (newest_ - pending_.begin()->first > window_) {
      stats_.incomplete_frames += assembler_.DiscardBefore(newest_ - window_);
      return true;
    }
  }
  stats_.damaged_log_stretches = log_.damaged_stretches();
  stats_.skipped_log_bytes = log_.skipped_bytes();
  log_done_ = true;
  return false;
}

bool SessionReader::Next(FrameSet* set) {
  while (!log_done_ && (pending_.empty() || newest_ - pending_.begin()->first <= window_)) ReadMore();
  if (pending_.empty()) return false;
  auto first = pending_.begin();
  *set = std::move(first->second);
  pending_.erase(first);
  emitted_any_ = true;
  last_emitted_ = set->frame_number;
  if (log_done_ && pending_.empty()) stats_.incomplete_frames += assembler_.pending();
  return true;
}

std::vector<std::string> SessionReader::warnings() const {
  std::vector<std::string> out;
  const std::string damage = log_.warning();
  if (!damage.empty()) out.push_back(damage);
  if (stats_.malformed)
    out.push_back(std::to_string(stats_.malformed) + " malformed datagrams dropped (first: " +
                  first_malformed_reason_ + ")");
  if (stats_.incomplete_frames)
    out.push_back(std::to_string(stats_.incomplete_frames) + " camera frames incomplete (lost chunks)");
  if (stats_.implausible_frames)
    out.push_back(std::to_string(stats_.implausible_frames) +
                  " camera frames skipped: frame number implausible (more than " + std::to_string(max_gap_) +
                  " frames past the session's frames)");
  for (const std::string& line : image_sizes_.Summary()) out.push_back(line);
  if (stats_.late_frames) out.push_back(std::to_string(stats_.late_frames) + " camera frames arrived too late");
  if (stats_.duplicate_frames)
    out.push_back(std::to_string(stats_.duplicate_frames) + " duplicate camera frames dropped");
  return out;
}

}  // namespace mocap

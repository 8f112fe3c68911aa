// A session directory: raw.mlog (every datagram as received), session.json (what the session
// is), and beside them whatever later steps write (calibration.json, truth.trc, markers.trc).
// Errors opening or writing files throw std::runtime_error naming the file; a damaged log is read
// past its damage (every good record is kept, session_log.h) and the damage is reported through
// warnings() and stats().
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "ingest/camera_frame.h"
#include "ingest/image_size_check.h"
#include "ingest/session_log.h"
#include "wire/chunking.h"

namespace mocap {

struct SessionInfo {
  double rate_hz = 0.0;
  uint64_t epoch_ns = 0;          // time of global frame 0 (trigger clock)
  bool free_run = false;          // frames grouped by capture time, not a trigger wire
  std::vector<uint32_t> camera_ids;
  uint64_t frame_sets = 0;        // distinct frame numbers written
  uint64_t camera_frames = 0;     // camera frames written
  uint64_t dropped_camera_frames = 0;
  std::string calibration = "calibration.json";
  std::string log = "raw.mlog";
  std::string source;             // "record", "sim project", ...
  nlohmann::json extra = nlohmann::json::object();  // free-form statistics and notes

  nlohmann::json ToJson() const;
  // Throws std::runtime_error on missing or mistyped required fields.
  static SessionInfo FromJson(const nlohmann::json& json);
};

SessionInfo LoadSessionInfo(const std::string& dir);
void SaveSessionInfo(const SessionInfo& info, const std::string& dir);

class SessionWriter {
 public:
  // What Create does when dir already holds a raw log: a recording is never overwritten (and a
  // second recorder into the same directory fails, the log being created exclusively); generated
  // sessions (the simulator's) are replaced.
  enum class Existing { kRefuse, kReplace };
  // Creates dir (if needed) and an empty raw log in it. Throws std::runtime_error.
  void Create(const std::string& dir, const SessionInfo& info, Existing existing = Existing::kRefuse);
  // Encodes the frame into its datagrams and appends them; flushes whenever the frame number
  // moves on, so a crash loses at most the frame in progress.
  void Write(const CameraFrame& frame);
  void AppendDatagram(const uint8_t* data, size_t size, uint64_t receive_time_ns);
  void Flush();
  SessionInfo& info() { return info_; }
  const std::string& dir() const { return dir_; }
  // Flushes the log and writes session.json.
  void Finish();

  // Write failures throw (`record`: the command ends), unless KeepFailures() was called: then
  // AppendDatagram and Flush keep the first failure's reason and errno and write nothing more,
  // so the caller (serve, whose frame path must go on) ends the capture at its next turn.
  void KeepFailures() { keep_failures_ = true; }
  const std::string& failure() const { return failure_; }
  int failure_errno() const { return failure_errno_; }

 private:
  template <typename Operation>
  void Guarded(Operation operation);

  std::string dir_;
  SessionInfo info_;
  SessionLogWriter log_;
  bool keep_failures_ = false;
  std::string failure_;
  int failure_errno_ = 0;
  uint64_t last_frame_number_ = ~0ull;
  bool any_frame_ = false;
};

struct SessionReadStats {
  uint64_t datagrams = 0;
  uint64_t malformed = 0;
  uint64_t other_packets = 0;     // status, preview, ... (not marker frames)
  uint64_t duplicate_chunks = 0;
  uint64_t inconsistent_chunks = 0;
  uint64_t incomplete_frames = 0;
  uint64_t late_frames = 0;       // arrived after their frame set was already handed out
  uint64_t duplicate_frames = 0;  // the same camera twice in one frame set
  uint64_t implausible_frames = 0;  // frame number out of the session's plausible range, skipped
  uint64_t rescaled_frames = 0;       // image size differs from the calibration's, same aspect ratio
  uint64_t wrong_size_frames = 0;     // image size of another aspect ratio: refused
  uint64_t damaged_log_stretches = 0;  // raw-log stretches that held no good record, skipped
  uint64_t skipped_log_bytes = 0;      // their bytes
};

// Frame numbers come off the wire and may be corrupt or forged (1e9, 2^63, UINT64_MAX), and
// every later stage steps through frame numbers, so the reader keeps them plausible: a camera
// frame is skipped (and counted in implausible_frames) when its number lies more than
// MaxFrameGap(info) frames past the newest frame accepted so far, or, for the first frame, past
// the number its receive time implies ((receive - epoch_ns) * rate_hz). The bound is a pause of
// kMaxPauseSeconds at the session's rate; longer pauses are not expected within one recording.
inline constexpr double kMaxPauseSeconds = 600.0;
uint64_t MaxFrameGap(const SessionInfo& info);

class SessionReader {
 public:
  // reorder_window: how many frame numbers a camera frame may arrive behind the newest one.
  explicit SessionReader(uint64_t reorder_window = 64) : window_(reorder_window) {}
  void Open(const std::string& dir);
  // The calibration's image sizes: camera frames of another size are then rescaled or refused
  // (image_size_check.h) and counted. Without it frames are used as recorded.
  void CheckImageSizes(ImageSizes calibrated) { image_sizes_ = ImageSizeCheck(std::move(calibrated)); }
  // Next frame set in frame-number order; false at the end.
  bool Next(FrameSet* set);
  const SessionInfo& Info() const { return info_; }
  const std::string& dir() const { return dir_; }
  const SessionReadStats& stats() const { return stats_; }
  std::vector<std::string> warnings() const;

 private:
  bool ReadMore();
  bool Plausible(uint64_t frame_number, uint64_t receive_time_ns) const;

  uint64_t window_;
  std::string dir_;
  SessionInfo info_;
  SessionLogReader log_;
  wire::ChunkAssembler assembler_;
  ImageSizeCheck image_sizes_;
  std::map<uint64_t, FrameSet> pending_;
  uint64_t newest_ = 0;
  bool accepted_any_ = false;
  uint64_t max_gap_ = 0;
  bool emitted_any_ = false;
  uint64_t last_emitted_ = 0;
  bool log_done_ = false;
  SessionReadStats stats_;
  std::string first_malformed_reason_;
};

}  // namespace mocap

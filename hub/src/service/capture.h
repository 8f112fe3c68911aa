// Captures on command: named sessions under the sessions directory, in the format `record`
// writes (raw.mlog with every datagram as received, session.json, the calibration beside them),
// flushed at least every 50 ms so a killed service loses at most that much; beside them
// live_points.tsv (io/live_points.h), every point published while capturing, as published. session.json says
// "capture_state": "capturing" while one runs and "complete" when it was stopped; a session a
// killed service left "capturing" is marked "interrupted" at the next start (it stays readable:
// `reconstruct` reads it up to its last flushed record). A capture whose writes fail (the disk
// is full, or its free space fell below `stop_free_mb`) ends "failed" with its reason, and the
// service goes on; session.json's counts are rewritten every second while capturing.
//
// `record` is serve's loop run headless with one capture of its own (`DirectCapture`): into a
// directory it names (not under a sessions directory, so it takes no sessions-directory lock and
// recovers nothing; but a directory that is some serve's sessions directory, with its
// ".serve.lock", is locked as a serve does, so no serve relabels the running recording), ending by
// itself at its limits (frame sets, the kernel receive time, silence), and telling each frame it
// counted to the caller (record's live markers.trc).
#pragma once

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "ingest/camera_frame.h"
#include "ingest/ingest_stats.h"
#include "ingest/session.h"
#include "pipeline/live_frame.h"
#include "service/session_name.h"

namespace mocap::service {

// Free space on the sessions disk: a capture needs `start_free_mb` to start, warns once below
// `warn_free_mb` and is stopped ("failed: disk full") below `stop_free_mb`, checked every
// `check_every_s`. A small file of `reserve_kb` is kept in each running session (".reserve") and
// removed when it ends, so that session.json can still be written on a disk a capture filled.
struct CaptureDiskOptions {
  double start_free_mb = 256.0;
  double warn_free_mb = 1024.0;
  double stop_free_mb = 64.0;
  double check_every_s = 0.25;
  double reserve_kb = 64.0;

  // "" or the refusal naming the field, its value and the rule.
  std::string Check() const;
};

// Bytes available to this process on the file system holding `path` (statvfs); throws
// std::runtime_error when it cannot be asked.
uint64_t FreeBytes(const std::string& path);

// Each frame set a capture counted, as published (on the loop).
using CapturedFrame = std::function<void(const FrameSet&, const pipeline::LiveFrame&)>;

// A capture into a directory of the caller's choosing that ends by itself (`record`). A limit of 0
// is none; once one is reached, limit_reached() turns true and the loop ends (HubService::Run).
struct DirectCapture {
  std::string dir;                 // created; refused when it holds a raw log already (never overwritten)
  std::string source = "record";   // session.json "source"
  uint64_t max_frame_sets = 0;     // frame sets after the Nth are not counted
  // Datagrams the kernel received at or after this are not logged and frame sets whose last
  // datagram came then are not counted (record --duration: counted from the bind).
  uint64_t end_receive_ns = 0;
  uint64_t idle_ns = 0;            // ends after this long without a datagram once one came
  CapturedFrame on_frame;          // may be empty
};

class Captures {
 public:
  using FreeBytesFunction = std::function<uint64_t(const std::string&)>;

  // `base` is the session description every capture starts from (rate, epoch, cameras).
  Captures(std::string sessions_dir, std::string calibration_file, SessionInfo base,
           CaptureDiskOptions disk = {}, FreeBytesFunction free_bytes = FreeBytes);
  ~Captures();
  Captures(const Captures&) = delete;
  Captures& operator=(const Captures&) = delete;

  // Creates the sessions directory and takes its lock (flock on ".serve.lock", holding the pid)
  // for this object's life. Throws std::runtime_error naming the directory and the holder when
  // another serve has it: two services would relabel each other's captures. Nothing without a
  // sessions directory ("": record's hub, whose one capture is a DirectCapture).
  void Lock();

  // The calibration file copied into the sessions started from now on (a new one was applied).
  void SetCalibrationFile(std::string calibration_file) { calibration_file_ = std::move(calibration_file); }
  // Sessions a killed service left capturing are marked interrupted; returns their names.
  std::vector<std::string> RecoverInterrupted();
  // Throws ApiError: 400 bad name, 409 a capture is running or the session exists, 507 the
  // disk has less than start_free_mb, 500 I/O.
  void Start(const std::string& name, const IngestStats& stats, uint64_t now_ns);
  // The one capture of `record` (see DirectCapture); the same refusals as Start (400 for an
  // empty dir; 409 when the directory is a sessions directory another serve or record holds),
  // and 500 with SessionWriter's "holds a recorded session already" for a directory with a raw log.
  void StartDirect(DirectCapture capture, const IngestStats& stats, uint64_t now_ns);
  // Throws ApiError 409 when none is running. Returns the finished session's summary.
  nlohmann::json Stop(const IngestStats& stats, uint64_t now_ns);
  // Where the loop appends datagrams; null when nothing is being captured. Its write failures
  // are kept (SessionWriter::KeepFailures) and end the capture at the next Tick.
  SessionWriter* writer() { return writer_.get(); }
  // The writer for one datagram received at receive_time_ns: null past a direct capture's end.
  SessionWriter* WriterFor(uint64_t receive_time_ns);
  // The capture's housekeeping, every loop turn: the raw log flushed every 50 ms, a failed write
  // or a disk below stop_free_mb ends it "failed" (returned: its summary, else null), the free
  // space watched, session.json's counts rewritten every second.
  nlohmann::json Tick(const IngestStats& stats, uint64_t now_ns);
  // A frame published while capturing (of `set`): counted and its points kept, unless a direct
  // capture's limits leave it out.
  void AddPublished(const pipeline::LiveFrame& frame, const FrameSet& set = FrameSet());
  // A direct capture reached one of its limits (the loop ends; the capture ends with it).
  bool limit_reached() const { return limit_reached_; }

  bool running() const { return writer_ != nullptr; }
  const std::string& name() const { return name_; }  // the running capture's
  const std::string& dir() const { return dir_; }  // the sessions directory ("" for record's hub)
  nlohmann::json Current(uint64_t now_ns) const;  // null when none
  // The last capture that ended (complete or failed, with its reason), null before any.
  const nlohmann::json& last() const { return last_; }
  // The sessions disk: free bytes at the last check and whether that is below warn_free_mb.
  nlohmann::json Disk() const;
  nlohmann::json List() const;                    // every session directory with its state
  // One session: its summary as in List() plus "files": [{"name", "bytes"}] (the regular files
  // directly in its directory, sorted; links and subdirectories are not offered) and
  // "processed": [{"recipe", "files"}] (its results, SESSION/processed/RECIPE/). Throws
  // ApiError 404 when there is no such session.
  nlohmann::json Describe(const std::string& name) const;
  // The path of one of those files, for download. Throws ApiError 404 unless both names are
  // valid session names (ValidSessionName: no '/', no leading '.', so nothing outside the
  // sessions directory can be named) and the file is a regular file (not a link) there.
  std::string FilePath(const std::string& name, const std::string& file) const;
  // Likewise one file of the results of a recipe (SESSION/processed/RECIPE/FILE).
  std::string ProcessedFilePath(const std::string& name, const std::string& recipe, const std::string& file) const;
  // The directory of a recipe's results (ApiError 404 as above).
  std::string ProcessedDirPath(const std::string& name, const std::string& recipe) const;

  // The operator's housekeeping (console and API). None touches the running capture (409); the
  // caller refuses sessions its processing jobs use. Errors: ApiError 404 no such session, 400 a
  // name a session cannot have or notes too long, 409 the running capture or a name taken, 500 I/O.
  // Delete moves the session whole into the sessions directory's .deleted/ (as NAME.<UTC time>),
  // so that a click loses nothing recorded; removing that directory frees the disk. Answers
  // {"name", "moved_to"}.
  nlohmann::json Delete(const std::string& name, uint64_t now_ns);
  // Renames the session's directory; answers its summary under the new name.
  nlohmann::json Rename(const std::string& name, const std::string& new_name);
  // The notes on a session (NOTES_FILE in its directory, at most kMaxNotesBytes of text; empty
  // removes them), shown as "notes" in its summary. Answers the summary.
  nlohmann::json SetNotes(const std::string& name, const std::string& notes);
  static constexpr const char* kNotesFile = "notes.txt";
  static constexpr size_t kMaxNotesBytes = 16384;

 private:
  nlohmann::json Summary(const std::filesystem::path& path) const;
  static nlohmann::json FilesJson(const std::filesystem::path& dir);
  std::filesystem::path SessionPath(const std::string& name) const;  // throws ApiError 404
  // SessionPath of a session that is not the running capture (409 when it is).
  std::filesystem::path IdleSessionPath(const std::string& name) const;
  // Start's work once the name (or directory) is judged: the session created at `path`.
  void Begin(const std::filesystem::path& path, const std::string& name, const std::string& source,
             const IngestStats& stats, uint64_t now_ns);
  // The flock on dir/.serve.lock; throws std::runtime_error naming the holder.
  static int LockDirectory(const std::string& dir);
  // The counts since the start into session.json's description.
  void UpdateInfo(const IngestStats& stats);
  // Ends the running capture "failed" with `reason`; returns its summary.
  nlohmann::json Fail(const std::string& reason, const IngestStats& stats, uint64_t now_ns);
  void RemoveReserve();
  void Ended();
  const std::string& DiskPath() const { return dir_.empty() ? path_ : dir_; }  // whose free space counts  // the running capture's writer, limits and lock let go
  bool CheckSpace(uint64_t now_ns);  // false: below stop_free_mb
  // "disk full" when the disk is (nearly) full, else `error`.
  std::string ReasonFor(const std::string& error);

  CaptureDiskOptions disk_;
  FreeBytesFunction free_bytes_;
  int lock_fd_ = -1;

  std::string dir_;
  std::string path_;  // the running capture's directory
  std::string calibration_file_;
  SessionInfo base_;
  std::unique_ptr<SessionWriter> writer_;
  std::ofstream live_;
  std::string name_;
  uint64_t started_ns_ = 0;
  uint64_t last_flush_ns_ = 0;
  uint64_t frame_sets_ = 0;
  IngestStats at_start_;
  uint64_t last_check_ns_ = 0;
  uint64_t last_info_ns_ = 0;
  uint64_t free_ = 0;
  bool warned_ = false;
  nlohmann::json last_;
  DirectCapture direct_;  // the running capture's limits (all 0 for serve's named captures)
  int direct_lock_fd_ = -1;
  uint64_t last_datagram_ns_ = 0;
  bool limit_reached_ = false;
};

}  // namespace mocap::service

// Captures on command: named sessions under the sessions directory, in the format `record`
// writes (raw.mlog with every datagram as received, session.json, the calibration beside them),
// flushed at least every 50 ms so a killed service loses at most that much; beside them
// live_points.tsv (io/live_points.h), every point published while capturing, as published. session.json says
// "capture_state": "capturing" while one runs and "complete" when it was stopped; a session a
// killed service left "capturing" is marked "interrupted" at the next start (it stays readable:
// `reconstruct` reads it up to its last flushed record).
#pragma once

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "ingest/ingest_stats.h"
#include "ingest/session.h"
#include "service/live_reconstruction.h"

namespace mocap::service {

// Letters, digits, '.', '-', '_'; 1-64 characters, not starting with '.'.
bool ValidSessionName(const std::string& name);

class Captures {
 public:
  // `base` is the session description every capture starts from (rate, epoch, cameras).
  Captures(std::string sessions_dir, std::string calibration_file, SessionInfo base);

  // The calibration file copied into the sessions started from now on (a new one was applied).
  void SetCalibrationFile(std::string calibration_file) { calibration_file_ = std::move(calibration_file); }
  // Sessions a killed service left capturing are marked interrupted; returns their names.
  std::vector<std::string> RecoverInterrupted();
  // Throws ApiError: 400 bad name, 409 a capture is running or the session exists, 500 I/O.
  void Start(const std::string& name, const IngestStats& stats, uint64_t now_ns);
  // Throws ApiError 409 when none is running. Returns the finished session's summary.
  nlohmann::json Stop(const IngestStats& stats, uint64_t now_ns);
  // Where the loop appends datagrams; null when nothing is being captured.
  SessionWriter* writer() { return writer_.get(); }
  // Flushes the raw log when 50 ms passed since the last flush.
  void MaybeFlush(uint64_t now_ns);
  // A frame published while capturing: counted and its points kept.
  void AddPublished(const LiveFrame& frame);

  bool running() const { return writer_ != nullptr; }
  const std::string& name() const { return name_; }  // the running capture's
  const std::string& dir() const { return dir_; }
  nlohmann::json Current(uint64_t now_ns) const;  // null when none
  nlohmann::json List() const;                    // every session directory with its state
  // One session: its summary as in List() plus "files": [{"name", "bytes"}] (the regular files
  // directly in its directory, sorted; links and subdirectories are not offered). Throws
  // ApiError 404 when there is no such session.
  nlohmann::json Describe(const std::string& name) const;
  // The path of one of those files, for download. Throws ApiError 404 unless both names are
  // valid session names (ValidSessionName: no '/', no leading '.', so nothing outside the
  // sessions directory can be named) and the file is a regular file (not a link) there.
  std::string FilePath(const std::string& name, const std::string& file) const;

 private:
  nlohmann::json Summary(const std::filesystem::path& path) const;
  std::filesystem::path SessionPath(const std::string& name) const;  // throws ApiError 404

  std::string dir_;
  std::string calibration_file_;
  SessionInfo base_;
  std::unique_ptr<SessionWriter> writer_;
  std::ofstream live_;
  std::string name_;
  uint64_t started_ns_ = 0;
  uint64_t last_flush_ns_ = 0;
  uint64_t frame_sets_ = 0;
  IngestStats at_start_;
};

}  // namespace mocap::service

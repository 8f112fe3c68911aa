// TRC marker files (OpenSim / Motion Analysis format): reader for files from other tools and a
// writer OpenSim accepts, in one-shot and streaming (flushed frame by frame) forms.
// Errors follow the io layer policy: std::runtime_error "<file>: line N: <reason>".
#pragma once

#include <cstdio>
#include <string>
#include <vector>

#include "io/marker_trajectories.h"

namespace mocap {

struct TrcReadOptions {
  // Files in metres or centimetres are converted to millimetres, the unit of the whole hub.
  bool convert_to_mm = true;
  // Older tools write a missing marker as exactly (0, 0, 0) (running.trc's L.Bicep is such a
  // column); a real marker sitting exactly on the origin is far less likely than that.
  bool zero_is_gap = true;
};

// Reads a whole TRC file. Accepts trailing tabs, blank lines, long header lines, empty cells
// (gaps) and padded numbers. Frame numbers come from the Time column (round(time * rate)) so
// that files align by time whatever their Frame# numbering; if Time is missing they come from
// Frame# - 1.
MarkerTrajectories ReadTrc(const std::string& path, const TrcReadOptions& options = {});
// The same from text already in memory; `source` names it in error messages (fuzzing, tests).
MarkerTrajectories ParseTrc(const std::string& text, const std::string& source,
                            const TrcReadOptions& options = {});

// Streaming writer: the header goes out on Open, each WriteFrame is flushed to the kernel, and
// Close patches NumFrames (written as a fixed-width padded field, as some OpenSim files do).
// A crash leaves a readable file whose NumFrames is too small; the reader trusts the rows.
class TrcWriter {
 public:
  TrcWriter() = default;
  ~TrcWriter();
  TrcWriter(const TrcWriter&) = delete;
  TrcWriter& operator=(const TrcWriter&) = delete;

  // Names fix the column count for the whole file; rate_hz > 0.
  void Open(const std::string& path, const std::vector<std::string>& names, double rate_hz);
  // `points` holds one entry per marker (NaN = gap). Frames must be written in increasing
  // frame-number order.
  void WriteFrame(uint64_t frame_number, const Eigen::Vector3d* points, size_t count);
  void WriteFrame(uint64_t frame_number, const std::vector<Eigen::Vector3d>& points) {
    WriteFrame(frame_number, points.data(), points.size());
  }
  void Close();
  bool is_open() const { return file_ != nullptr; }
  uint64_t frames_written() const { return frames_; }

 private:
  void Fail(const std::string& reason) const;

  std::FILE* file_ = nullptr;
  std::string path_;
  size_t num_markers_ = 0;
  double rate_hz_ = 0.0;
  uint64_t frames_ = 0;
  uint64_t first_frame_ = 0;
  uint64_t last_frame_ = 0;
  long num_frames_offset_ = -1;
  long orig_num_frames_offset_ = -1;
  long start_frame_offset_ = -1;
};

// One-shot write of a whole MarkerTrajectories.
void WriteTrc(const MarkerTrajectories& trajectories, const std::string& path);

}  // namespace mocap

// C3D marker files (the biomechanics exchange format, https://www.c3d.org): a streaming writer
// and a reader, Intel byte order, floating-point point data in millimetres.
//
// What is written: the header block; groups POINT (USED, SCALE = -1, RATE, DATA_START, FRAMES,
// LONG_FRAMES past 65535 frames, LABELS/LABELS2... and DESCRIPTIONS/DESCRIPTIONS2... in chunks of
// 255, UNITS "mm"), ANALOG (USED 0), TRIAL (ACTUAL_START_FIELD / ACTUAL_END_FIELD: the session's
// frame numbers + 1, so files keep their place in the session) and MANUFACTURER; then one record
// per frame, 4 floats per point: x, y, z and the residual word (-1: a gap, as the standard says;
// otherwise the caller's residual, 0 by default: the standard's "not a measurement, computed"; an
// edited take writes a positive residual for measured samples and 0 for filled ones, edit/).
// Frames are contiguous: frame numbers skipped by the caller become rows of gaps.
// The reader takes files from other tools too: Intel integer or float data, any analog data
// (skipped), labels beyond 255 points; DEC and MIPS files are refused with that reason.
// Errors follow the io layer policy: std::runtime_error "<file>: <reason>". Memory and time
// follow the file's size, never the numbers written in it.
#pragma once

#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "io/marker_trajectories.h"

namespace mocap {

class C3dWriter {
 public:
  C3dWriter() = default;
  ~C3dWriter();
  C3dWriter(const C3dWriter&) = delete;
  C3dWriter& operator=(const C3dWriter&) = delete;

  // Names fix the point count for the whole file (at most 32767, each at most 255 bytes);
  // rate_hz > 0. Writes header and parameters; Close() fills in the frame counts.
  void Open(const std::string& path, const std::vector<std::string>& names, double rate_hz);
  // One entry per point (NaN: a gap). Frame numbers must increase; a skipped one becomes a row
  // of gaps (at most kMaxSkippedFrames at once, so a corrupt frame number cannot fill a disk).
  // residuals: one per point (the residual word of a point that is not a gap), or null for 0.
  void WriteFrame(uint64_t frame_number, const Eigen::Vector3d* points, size_t count, const float* residuals = nullptr);
  void Close();
  bool is_open() const { return file_ != nullptr; }
  uint64_t frames_written() const { return frames_; }

  static constexpr uint64_t kMaxSkippedFrames = 10 * 60 * 1000;  // 10 min at 1 kHz

 private:
  void WriteRow(const Eigen::Vector3d* points, const float* residuals);
  void Fail(const std::string& reason) const;

  std::FILE* file_ = nullptr;
  std::string path_;
  size_t num_points_ = 0;
  uint64_t frames_ = 0;
  uint64_t first_frame_ = 0;
  uint64_t next_frame_ = 0;
  std::vector<long> patch_frames_int16_;  // file offsets of 16-bit frame counts
  long patch_long_frames_ = -1;           // POINT:LONG_FRAMES (float)
  long patch_end_field_ = -1;             // TRIAL:ACTUAL_END_FIELD
  long patch_start_field_ = -1;           // TRIAL:ACTUAL_START_FIELD
  std::vector<float> row_;
};

// residuals: frame-major like trajectories.points, or null (every residual 0).
void WriteC3d(const MarkerTrajectories& trajectories, const std::string& path,
              const std::vector<float>* residuals = nullptr);

// residuals, when given: the residual word of every point as read (frame-major; -1 for a gap).
MarkerTrajectories ReadC3d(const std::string& path, std::vector<float>* residuals = nullptr);
// The same from bytes in memory; `source` names it in error messages (fuzzing, tests).
MarkerTrajectories ParseC3d(const std::vector<uint8_t>& bytes, const std::string& source,
                            std::vector<float>* residuals = nullptr);

}  // namespace mocap

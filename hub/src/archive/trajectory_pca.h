// PCA compression of marker trajectories (seed 003, chapter 6, turned to marker data): the
// recording is cut into windows of a few seconds; within a window each group of markers (the whole
// body, or one segment) is a matrix of frames x coordinates, centred on each coordinate's mean and
// reduced to its K leading singular components (Eigen's BDCSVD); both factors are quantised with
// steps sized from the error budget left after the truncation (each component's weights with a
// step inverse to its singular value, so that every component adds the same error), which keeps
// the integers small: the file stores them as varints, the time factors as second differences
// (smooth motion makes them a byte or less). K is the user's (components) or the smallest that
// keeps the window's RMS 3D error, measured after quantisation, within max_error_mm. Gaps stay gaps:
// they are filled by linear interpolation for the decomposition only and kept as a per-marker run
// list, so the decoder puts NaN back exactly where the input had none.
// Errors: std::invalid_argument from Check() (the hub's options policy) and for inputs that
// cannot be compressed (no frames, markers in no group or in two).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "io/marker_trajectories.h"

namespace mocap {

// Limits shared by the compressor and the archive reader (archive_format.h): they bound the
// memory a file can make the reader allocate.
constexpr uint32_t kMaxArchiveMarkers = 4096;
constexpr uint32_t kMaxArchiveWindowFrames = 4096;
constexpr uint32_t kMaxArchiveComponents = 255;
// Points (frames x markers) a decoded archive may hold: 2^28, 6 GiB of points; an hour of 123
// markers at 240 Hz is 1.1e8.
constexpr uint64_t kMaxArchivePoints = uint64_t{1} << 28;

struct TrajectoryPcaOptions {
  // Frames per window (1..kMaxArchiveWindowFrames).
  int window_frames = 120;
  // Fixed number of components per window and group (1..255, at most the window's rank); 0: chosen
  // by max_error_mm.
  int components = 0;
  // RMS 3D error bound per window and group, mm (> 0), when components is 0.
  double max_error_mm = 0.5;
  // RMS 3D error the quantisation may add with a fixed number of components, mm (> 0).
  double quantisation_mm = 0.05;

  void Check() const;
};

// Integers of the quantised factors are at most this in magnitude (they travel as 32-bit
// zigzag varints, the time factors' second differences too).
constexpr int32_t kMaxArchiveInteger = (int32_t{1} << 29) - 1;

// Quantisation step of the blocks' means, mm (2^-8: adds 0.002 mm RMS 3D error; means within
// +-2 km).
constexpr double kArchiveMeanStepMm = 1.0 / 256.0;

// One group's window: x[t][c] = kArchiveMeanStepMm * mean[c] + sum_k time_step * time[t * K + k] *
// weight_steps[k] * weights[c * K + k], c = 3 * (marker in group) + axis.
struct PcaBlock {
  int components = 0;
  std::vector<int32_t> mean;         // 3 * group size, in kArchiveMeanStepMm
  float time_step = 0.0f;            // > 0 when K > 0
  std::vector<int32_t> time;         // frames in window x K, row-major
  std::vector<float> weight_steps;   // K, each > 0
  std::vector<int32_t> weights;      // 3 * group size x K, row-major
};

struct CompressedTrajectories {
  double rate_hz = 0.0;
  std::vector<std::string> names;
  std::vector<uint64_t> frame_numbers;
  int window_frames = 0;
  std::vector<std::vector<int>> groups;  // marker indices; every marker in exactly one group
  // Per marker: lengths of alternating runs over all frames, present first (a run may be 0).
  std::vector<std::vector<uint32_t>> gap_runs;
  // Window-major: blocks[window * groups.size() + group].
  std::vector<PcaBlock> blocks;

  size_t NumFrames() const { return frame_numbers.size(); }
  size_t NumWindows() const {
    return window_frames > 0 ? (NumFrames() + static_cast<size_t>(window_frames) - 1) / window_frames : 0;
  }
};

// Groups: the whole body (one group of every marker) when empty.
CompressedTrajectories CompressTrajectories(const MarkerTrajectories& trajectories,
                                            const std::vector<std::vector<int>>& groups,
                                            const TrajectoryPcaOptions& options);

// Expects a consistent structure (archive_format.cc's reader checks every size before this runs).
MarkerTrajectories DecompressTrajectories(const CompressedTrajectories& compressed);

// Root mean square 3D distance over the points present in both (same shape required).
double TrajectoryRmsError(const MarkerTrajectories& reference, const MarkerTrajectories& other);

}  // namespace mocap

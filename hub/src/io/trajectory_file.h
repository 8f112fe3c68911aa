// Marker files by extension: `.trc` (OpenSim, io/trc.h) or `.c3d` (io/c3d.h), for every command
// that reads or writes trajectories; a capture's `live_points.tsv` (io/live_points.h, any `.tsv`)
// is read too, never written (serve writes it). Errors: std::invalid_argument for any other
// extension (or writing a .tsv), otherwise the formats' own std::runtime_error.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "io/c3d.h"
#include "io/marker_trajectories.h"
#include "io/trc.h"

namespace mocap {

enum class TrajectoryFormat { kTrc, kC3d, kLivePoints };

// From the file name's extension (case-insensitive).
TrajectoryFormat TrajectoryFormatOf(const std::string& path);
// The same for a file to write: refuses live points (std::invalid_argument).
TrajectoryFormat OutputTrajectoryFormatOf(const std::string& path);

// Live points: each track its own column as io/live_points.h reads them.
MarkerTrajectories ReadTrajectories(const std::string& path);
void WriteTrajectories(const MarkerTrajectories& trajectories, const std::string& path);

// Streaming writer of either format (same contract as TrcWriter and C3dWriter).
class TrajectoryWriter {
 public:
  void Open(const std::string& path, const std::vector<std::string>& names, double rate_hz);
  void WriteFrame(uint64_t frame_number, const std::vector<Eigen::Vector3d>& points);
  void Close();

 private:
  std::unique_ptr<TrcWriter> trc_;
  std::unique_ptr<C3dWriter> c3d_;
};

}  // namespace mocap

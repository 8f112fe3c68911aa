// Marker files by extension (see trajectory_file.h).
#include "io/trajectory_file.h"

#include <algorithm>
#include <cctype>
#include <stdexcept>

#include "io/live_points.h"

namespace mocap {

TrajectoryFormat TrajectoryFormatOf(const std::string& path) {
  const size_t dot = path.find_last_of('.');
  std::string ext = dot == std::string::npos ? "" : path.substr(dot + 1);
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (ext == "trc") return TrajectoryFormat::kTrc;
  if (ext == "c3d") return TrajectoryFormat::kC3d;
  if (ext == "tsv") return TrajectoryFormat::kLivePoints;
  throw std::invalid_argument("'" + path + "': marker files are .trc or .c3d (or a capture's live_points.tsv, read only)");
}

TrajectoryFormat OutputTrajectoryFormatOf(const std::string& path) {
  const TrajectoryFormat format = TrajectoryFormatOf(path);
  if (format == TrajectoryFormat::kLivePoints)
    throw std::invalid_argument("'" + path + "': marker files are written as .trc or .c3d (live points are serve's own record)");
  return format;
}

MarkerTrajectories ReadTrajectories(const std::string& path) {
  switch (TrajectoryFormatOf(path)) {
    case TrajectoryFormat::kC3d:
      return ReadC3d(path);
    case TrajectoryFormat::kLivePoints:
      return ReadLivePoints(path).points;
    case TrajectoryFormat::kTrc:
      break;
  }
  return ReadTrc(path);
}

void WriteTrajectories(const MarkerTrajectories& trajectories, const std::string& path) {
  if (OutputTrajectoryFormatOf(path) == TrajectoryFormat::kC3d)
    WriteC3d(trajectories, path);
  else
    WriteTrc(trajectories, path);
}

void TrajectoryWriter::Open(const std::string& path, const std::vector<std::string>& names, double rate_hz) {
  if (OutputTrajectoryFormatOf(path) == TrajectoryFormat::kC3d) {
    c3d_ = std::make_unique<C3dWriter>();
    c3d_->Open(path, names, rate_hz);
  } else {
    trc_ = std::make_unique<TrcWriter>();
    trc_->Open(path, names, rate_hz);
  }
}

void TrajectoryWriter::WriteFrame(uint64_t frame_number, const std::vector<Eigen::Vector3d>& points) {
  if (c3d_) c3d_->WriteFrame(frame_number, points.data(), points.size());
  if (trc_) trc_->WriteFrame(frame_number, points);
}

void TrajectoryWriter::Close() {
  if (c3d_) c3d_->Close();
  if (trc_) trc_->Close();
}

}  // namespace mocap

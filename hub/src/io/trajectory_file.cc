// Marker files by extension (see trajectory_file.h).
#include "io/trajectory_file.h"

#include <algorithm>
#include <cctype>
#include <stdexcept>

namespace mocap {

TrajectoryFormat TrajectoryFormatOf(const std::string& path) {
  const size_t dot = path.find_last_of('.');
  std::string ext = dot == std::string::npos ? "" : path.substr(dot + 1);
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (ext == "trc") return TrajectoryFormat::kTrc;
  if (ext == "c3d") return TrajectoryFormat::kC3d;
  throw std::invalid_argument("'" + path + "': marker files are .trc or .c3d");
}

MarkerTrajectories ReadTrajectories(const std::string& path) {
  return TrajectoryFormatOf(path) == TrajectoryFormat::kC3d ? ReadC3d(path) : ReadTrc(path);
}

void WriteTrajectories(const MarkerTrajectories& trajectories, const std::string& path) {
  if (TrajectoryFormatOf(path) == TrajectoryFormat::kC3d)
    WriteC3d(trajectories, path);
  else
    WriteTrc(trajectories, path);
}

void TrajectoryWriter::Open(const std::string& path, const std::vector<std::string>& names, double rate_hz) {
  if (TrajectoryFormatOf(path) == TrajectoryFormat::kC3d) {
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

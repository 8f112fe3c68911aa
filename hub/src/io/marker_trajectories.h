// In-memory marker trajectories shared by io (TRC), recon, track, sim and eval: one row per
// frame, one column per marker, gaps as NaN points. Millimetres; frame numbers are the global
// frame numbers of the session, so Time = frame_number / rate_hz.
#pragma once

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace mocap {

struct MarkerTrajectories {
  double rate_hz = 0.0;
  std::vector<std::string> names;
  std::vector<uint64_t> frame_numbers;
  // Frame-major: points[frame_index * names.size() + marker]. A gap is a NaN point; a flat array
  // keeps long sessions compact and lets callers pass a whole frame as one contiguous range.
  std::vector<Eigen::Vector3d> points;

  size_t NumFrames() const { return frame_numbers.size(); }
  size_t NumMarkers() const { return names.size(); }

  static Eigen::Vector3d Gap() { return Eigen::Vector3d::Constant(std::nan("")); }
  static bool IsGap(const Eigen::Vector3d& point) { return !point.allFinite(); }

  const Eigen::Vector3d& At(size_t frame_index, size_t marker) const {
    return points[frame_index * names.size() + marker];
  }
  Eigen::Vector3d& At(size_t frame_index, size_t marker) {
    return points[frame_index * names.size() + marker];
  }
  bool Has(size_t frame_index, size_t marker) const { return !IsGap(At(frame_index, marker)); }

  // Appends a frame full of gaps and returns its index.
  size_t AddFrame(uint64_t frame_number) {
    frame_numbers.push_back(frame_number);
    points.resize(points.size() + names.size(), Gap());
    return frame_numbers.size() - 1;
  }

  double TimeOf(size_t frame_index) const {
    return static_cast<double>(frame_numbers[frame_index]) / rate_hz;
  }
};

// M001, M002, ... (1-based) for output markers that have no name from a marker list.
std::string DefaultMarkerName(size_t index);
// True for the hub's anonymous names (M followed by digits, as DefaultMarkerName writes): such a
// column carries no name, whatever a truth file happens to call its markers.
bool IsAnonymousMarkerName(const std::string& name);

// The axis along which a body is tallest: the median over frames of the spread of the markers
// along each axis. A standing, walking or running person is 1.5-1.9 m tall and at most about
// 1 m wide or deep in any one frame, whatever the distance travelled. Returns -1 when no frame
// has at least three markers.
int DetectUpAxis(const MarkerTrajectories& motion);

}  // namespace mocap

// A take under edit: the marker trajectories and, for every sample, whether it was measured or
// filled (and by which method). The edit operations (edit_apply.h) move the marks with the samples,
// so an output can say which of its samples are measurements (io/c3d.h residuals, the side file of
// filled_marks.h).
#pragma once

#include <cstdint>
#include <vector>

#include "io/marker_trajectories.h"

namespace mocap::edit {

enum class FillMethod : uint8_t { kSpline = 1, kLinear, kPattern, kRigid, kRelational };

const char* FillMethodName(FillMethod method);

struct EditedTake {
  MarkerTrajectories markers;
  // Frame-major like markers.points: 0 measured (or a gap), otherwise the FillMethod that made it.
  std::vector<uint8_t> marks;

  // Every present sample counted as measured.
  static EditedTake FromMeasured(MarkerTrajectories markers);

  uint8_t Mark(size_t frame_index, size_t marker) const { return marks[frame_index * markers.NumMarkers() + marker]; }
  bool Filled(size_t frame_index, size_t marker) const { return Mark(frame_index, marker) != 0; }
  void Set(size_t frame_index, size_t marker, const Eigen::Vector3d& point, uint8_t mark) {
    markers.At(frame_index, marker) = point;
    marks[frame_index * markers.NumMarkers() + marker] = mark;
  }
  void Clear(size_t frame_index, size_t marker) { Set(frame_index, marker, MarkerTrajectories::Gap(), 0); }

  // The column of `name`, or -1.
  long Find(const std::string& name) const;
  // Appends a column of gaps; removes one (samples and marks).
  void AddColumn(const std::string& name);
  void RemoveColumn(size_t marker);
  // The frame index of frame number `frame`: the first index at or after it (NumFrames() if none).
  size_t IndexAtOrAfter(uint64_t frame) const;
};

}  // namespace mocap::edit

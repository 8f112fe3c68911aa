// EditedTake's column bookkeeping (see edited_take.h).
#include "edit/edited_take.h"

#include <algorithm>

namespace mocap::edit {

const char* FillMethodName(FillMethod method) {
  switch (method) {
    case FillMethod::kSpline: return "spline";
    case FillMethod::kLinear: return "linear";
    case FillMethod::kPattern: return "pattern";
    case FillMethod::kRigid: return "rigid";
    case FillMethod::kRelational: return "relational";
  }
  return "?";
}

EditedTake EditedTake::FromMeasured(MarkerTrajectories markers) {
  EditedTake take;
  take.markers = std::move(markers);
  take.marks.assign(take.markers.points.size(), 0);
  return take;
}

long EditedTake::Find(const std::string& name) const {
  const auto it = std::find(markers.names.begin(), markers.names.end(), name);
  return it == markers.names.end() ? -1 : static_cast<long>(it - markers.names.begin());
}

void EditedTake::AddColumn(const std::string& name) {
  const size_t old_width = markers.NumMarkers(), frames = markers.NumFrames();
  std::vector<Eigen::Vector3d> points;
  std::vector<uint8_t> new_marks;
  points.reserve(frames * (old_width + 1));
  new_marks.reserve(frames * (old_width + 1));
  for (size_t f = 0; f < frames; ++f) {
    for (size_t m = 0; m < old_width; ++m) {
      points.push_back(markers.points[f * old_width + m]);
      new_marks.push_back(marks[f * old_width + m]);
    }
    points.push_back(MarkerTrajectories::Gap());
    new_marks.push_back(0);
  }
  markers.names.push_back(name);
  markers.points = std::move(points);
  marks = std::move(new_marks);
}

void EditedTake::RemoveColumn(size_t marker) {
  const size_t old_width = markers.NumMarkers(), frames = markers.NumFrames();
  size_t out = 0;
  for (size_t f = 0; f < frames; ++f)
    for (size_t m = 0; m < old_width; ++m) {
      if (m == marker) continue;
      markers.points[out] = markers.points[f * old_width + m];
      marks[out] = marks[f * old_width + m];
      ++out;
    }
  markers.points.resize(out);
  marks.resize(out);
  markers.names.erase(markers.names.begin() + static_cast<long>(marker));
}

size_t EditedTake::IndexAtOrAfter(uint64_t frame) const {
  const auto& numbers = markers.frame_numbers;
  return static_cast<size_t>(std::lower_bound(numbers.begin(), numbers.end(), frame) - numbers.begin());
}

}  // namespace mocap::edit

// The edited take's files (see edit_output.h).
#include "edit/edit_output.h"

#include <cstdio>
#include <stdexcept>

#include "io/c3d.h"
#include "io/trajectory_file.h"

namespace mocap::edit {

std::vector<FilledStretch> FilledStretches(const EditedTake& take) {
  std::vector<FilledStretch> out;
  const MarkerTrajectories& m = take.markers;
  for (size_t c = 0; c < m.NumMarkers(); ++c) {
    for (size_t f = 0; f < m.NumFrames(); ++f) {
      const uint8_t mark = take.Mark(f, c);
      if (mark == 0 || !m.Has(f, c)) continue;
      // The stretch of frame f - 1 of this column is the last one pushed.
      const bool extends = f > 0 && take.Mark(f - 1, c) == mark && m.Has(f - 1, c);
      if (extends) {
        out.back().last_frame = m.frame_numbers[f];
      } else {
        out.push_back({m.names[c], m.frame_numbers[f], m.frame_numbers[f], static_cast<FillMethod>(mark)});
      }
    }
  }
  return out;
}

std::string FilledSidePath(const std::string& output) {
  const size_t slash = output.find_last_of('/');
  const size_t dot = output.find_last_of('.');
  const bool has_ext = dot != std::string::npos && (slash == std::string::npos || dot > slash);
  return (has_ext ? output.substr(0, dot) : output) + ".filled.tsv";
}

void WriteEditedTake(const EditedTake& take, const std::string& path) {
  const MarkerTrajectories& m = take.markers;
  if (TrajectoryFormatOf(path) == TrajectoryFormat::kC3d) {
    std::vector<float> residuals(m.points.size());
    for (size_t i = 0; i < residuals.size(); ++i) residuals[i] = take.marks[i] != 0 ? 0.0f : kMeasuredResidual;
    WriteC3d(m, path, &residuals);
  } else {
    WriteTrajectories(m, path);
  }
  const std::string side = FilledSidePath(path);
  std::FILE* file = std::fopen(side.c_str(), "w");
  if (file == nullptr) throw std::runtime_error(side + ": cannot open for writing");
  std::fprintf(file, "# filled samples of %s (frames inclusive); every other present sample is measured\n",
               path.substr(path.find_last_of('/') + 1).c_str());
  std::fprintf(file, "marker\tfirst_frame\tlast_frame\tmethod\n");
  for (const FilledStretch& s : FilledStretches(take))
    std::fprintf(file, "%s\t%llu\t%llu\t%s\n", s.marker.c_str(), static_cast<unsigned long long>(s.first_frame),
                 static_cast<unsigned long long>(s.last_frame), FillMethodName(s.method));
  if (std::fclose(file) != 0) throw std::runtime_error(side + ": write failed (disk full?)");
}

}  // namespace mocap::edit

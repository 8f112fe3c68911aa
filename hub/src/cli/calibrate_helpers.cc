#include "cli/calibrate_helpers.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "calib/session_frames.h"
#include "cli/commands.h"
#include "util/log.h"

namespace mocap {

std::vector<Eigen::Vector3d> ParsePointList(const std::string& text, const std::string& option) {
  std::vector<Eigen::Vector3d> points;
  size_t start = 0;
  while (start <= text.size()) {
    const size_t end = std::min(text.find(';', start), text.size());
    const std::string item = text.substr(start, end - start);
    if (!item.empty()) {
      double x, y, z;
      char tail;
      if (std::sscanf(item.c_str(), " %lf , %lf , %lf %c", &x, &y, &z, &tail) != 3 ||
          !std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z)) {
        throw UsageError(option + ": '" + item + "' is not a point 'x,y,z' (mm)");
      }
      points.emplace_back(x, y, z);
    }
    start = end + 1;
  }
  if (points.empty()) throw UsageError(option + ": no points given");
  return points;
}

std::vector<FrameSet> LoadFramesReporting(const std::string& session) {
  std::vector<std::string> warnings;
  std::vector<FrameSet> frames = LoadSessionFrames(session, &warnings);
  for (const std::string& warning : warnings) log::Warn("{}", warning);
  return frames;
}

}  // namespace mocap

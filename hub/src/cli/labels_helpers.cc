// The labelling step of reconstruct and labels apply (see labels_helpers.h).
#include "cli/labels_helpers.h"

#include <stdexcept>

#include <fmt/format.h>

#include "labels/marker_set.h"
#include "labels/trial_labeller.h"

namespace mocap {

std::string ApplyMarkerSet(const std::string& marker_set_path, int up_axis, MarkerTrajectories* markers) {
  const MarkerSet set = ReadMarkerSetFile(marker_set_path);
  LabellerOptions options;
  options.up_axis = up_axis >= 0 ? up_axis : DetectUpAxis(*markers);
  TrialLabelling result;
  try {
    result = LabelTrajectories(*markers, set, options);
  } catch (const std::invalid_argument& error) {
    throw std::runtime_error(marker_set_path + ": " + error.what());
  }
  *markers = std::move(result.named);
  return fmt::format("{} of {} names placed, {:.2f}% of points named ({} runs of {}; {} points unnamed in frames "
                     "that broke their distances)",
                     result.names_placed, set.NumMarkers(),
                     result.points ? 100.0 * static_cast<double>(result.named_points) / result.points : 0.0,
                     result.named_runs, result.runs, result.frame_names_dropped);
}

}  // namespace mocap

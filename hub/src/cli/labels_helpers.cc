// The naming step of reconstruct and labels apply (see labels_helpers.h).
#include "cli/labels_helpers.h"

#include <stdexcept>

#include "labels/marker_set.h"
#include "pipeline/take_outputs.h"

namespace mocap {

std::string NameTakeFromFile(const std::string& marker_set_path, int up_axis, MarkerTrajectories* markers) {
  const MarkerSet set = ReadMarkerSetFile(marker_set_path);
  try {
    return pipeline::NameTake(set, up_axis, markers).Describe();
  } catch (const std::invalid_argument& error) {
    throw std::runtime_error(marker_set_path + ": " + error.what());
  }
}

}  // namespace mocap

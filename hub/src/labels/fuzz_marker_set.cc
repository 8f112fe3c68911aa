// libFuzzer entry for the marker-set reader: any bytes must load or throw runtime_error, and a
// set that loads must survive being written and read back, and label a frame without crashing.
#include <cstddef>
#include <cstdint>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "labels/marker_labeller.h"
#include "labels/marker_set.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const nlohmann::json document = nlohmann::json::parse(data, data + size, nullptr, /*allow_exceptions=*/false);
  if (document.is_discarded()) return 0;
  try {
    const mocap::MarkerSet set = mocap::MarkerSetFromJson(document, "fuzz");
    const mocap::MarkerSet again = mocap::MarkerSetFromJson(mocap::MarkerSetToJson(set), "fuzz-again");
    if (again.names != set.names || again.distances.size() != set.distances.size()) __builtin_trap();
    try {
      mocap::MarkerLabeller labeller(set);
      std::vector<Eigen::Vector3d> points;
      std::vector<int64_t> tracks;
      for (size_t i = 0; i < set.NumMarkers() && i < 64; ++i) {
        points.push_back(Eigen::Vector3d(100.0 * i, 50.0 * (i % 3), 1000.0 + 10.0 * i));
        tracks.push_back(static_cast<int64_t>(i));
      }
      for (int frame = 0; frame < 3; ++frame) labeller.Update(points, tracks);
    } catch (const std::invalid_argument&) {
      // a set without a mean shape cannot label: refused, as documented
    }
  } catch (const std::runtime_error&) {
  }
  return 0;
}

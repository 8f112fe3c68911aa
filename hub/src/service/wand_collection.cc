// Live wand collection (see wand_collection.h).
#include "service/wand_collection.h"

#include <cmath>

namespace mocap::service {

WandCollection::WandCollection(const Rig& rig, WandingOptions options, uint64_t now_ns)
    : options_((options.Check(), std::move(options))),
      coverage_(options_.intrinsics ? *options_.intrinsics : rig, options_.Wand().MarkerCount(), options_.coverage),
      start_ns_(now_ns) {}

bool WandCollection::EveryCameraHasEnough() const {
  for (size_t i = 0; i < coverage_.cameras().size(); ++i)
    if (!coverage_.Advise(i, options_.min_samples, options_.coverage_target).enough) return false;
  return !coverage_.cameras().empty();
}

std::string WandCollection::StopReason(uint64_t now_ns) const {
  if (EveryCameraHasEnough()) return "every camera has enough samples and coverage";
  const double elapsed = static_cast<double>(now_ns - start_ns_) * 1e-9;
  if (now_ns > start_ns_ && elapsed >= options_.timeout_s)
    return "timed out after " + std::to_string(static_cast<int>(std::lround(elapsed))) + " s";
  return "";
}

nlohmann::json WandCollection::Json(uint64_t now_ns) const {
  const WandCoverageOptions& grid = coverage_.options();
  nlohmann::json cameras = nlohmann::json::array();
  nlohmann::json advice = nlohmann::json::array();
  for (size_t i = 0; i < coverage_.cameras().size(); ++i) {
    const CameraCoverage& c = coverage_.cameras()[i];
    const CoverageAdvice a = coverage_.Advise(i, options_.min_samples, options_.coverage_target);
    cameras.push_back({{"id", c.id},
                       {"samples", c.samples},
                       {"coverage", c.Share(grid.cell_samples)},
                       {"enough", a.enough},
                       {"region", a.region},
                       {"advice", a.text},
                       {"counts", c.counts}});
    if (!a.enough) advice.push_back(a.text);
  }
  return {{"elapsed_s", now_ns > start_ns_ ? static_cast<double>(now_ns - start_ns_) * 1e-9 : 0.0},
          {"timeout_s", options_.timeout_s},
          {"frame_sets", coverage_.frame_sets()},
          {"wand_frames", coverage_.wand_frames()},
          {"min_samples", options_.min_samples},
          {"coverage_target", options_.coverage_target},
          {"grid", {{"columns", grid.columns}, {"rows", grid.rows}, {"cell_samples", grid.cell_samples}}},
          {"cameras", cameras},
          {"advice", advice}};
}

}  // namespace mocap::service

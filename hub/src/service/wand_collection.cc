// Live wand collection (see wand_collection.h).
#include "service/wand_collection.h"

#include <cmath>
#include <string>

namespace mocap::service {

WandCollection::WandCollection(const Rig& rig, WandingOptions options, uint64_t now_ns)
    : options_((options.Check(), std::move(options))),
      coverage_(options_.intrinsics ? *options_.intrinsics : rig,
                options_.SingleMarker() ? 1 : options_.Wand().MarkerCount(), options_.coverage),
      start_ns_(now_ns) {
  if (options_.SingleMarker())
    scale_.emplace(options_.intrinsics ? *options_.intrinsics : rig, options_.Wand().MarkerCount(), options_.coverage);
}

bool WandCollection::ScaleHasEnough() const { return !scale_ || scale_->wand_frames() >= options_.min_scale_frames; }

bool WandCollection::EveryCameraHasEnough() const {
  for (size_t i = 0; i < coverage_.cameras().size(); ++i)
    if (!coverage_.Advise(i, options_.min_samples, options_.coverage_target).enough) return false;
  return !coverage_.cameras().empty() && ScaleHasEnough();
}

std::string WandCollection::StopReason(uint64_t now_ns) const {
  if (EveryCameraHasEnough())
    return scale_ ? "every camera has enough samples and coverage, and the scale bar was seen"
                  : "every camera has enough samples and coverage";
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
  if (!ScaleHasEnough()) {
    advice.push_back("show the scale bar (two markers " + std::to_string(std::lround(options_.wand_length_mm)) +
                     " mm apart) to two or more cameras: " + std::to_string(scale_->wand_frames()) + " of " +
                     std::to_string(options_.min_scale_frames) + " frames");
  }
  return {{"mode", options_.mode},
          {"scale_frames", scale_ ? nlohmann::json(scale_->wand_frames()) : nlohmann::json(nullptr)},
          {"min_scale_frames", scale_ ? nlohmann::json(options_.min_scale_frames) : nlohmann::json(nullptr)},
          {"elapsed_s", now_ns > start_ns_ ? static_cast<double>(now_ns - start_ns_) * 1e-9 : 0.0},
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

// Live wand collection (see wand_collection.h).
#include "service/wand_collection.h"

#include <cmath>
#include <stdexcept>

#include "calib/wand_bundle_adjustment.h"
#include "service/api_error.h"
#include "service/capture.h"

namespace mocap::service {

WandGeometry WandingOptions::Wand() const {
  return middle_marker_mm > 0.0 ? WandGeometry::ThreeMarker(wand_length_mm, middle_marker_mm)
                                : WandGeometry::TwoMarker(wand_length_mm);
}

void WandingOptions::Check() const {
  if (!ValidSessionName(session))
    throw ApiError(400, "'name' must be 1-64 letters, digits, '.', '-' or '_', not starting with '.'");
  if (!(wand_length_mm >= 10.0 && wand_length_mm <= 5000.0)) throw ApiError(400, "'wand_length_mm' must be 10..5000");
  if (!(middle_marker_mm >= 0.0 && middle_marker_mm < wand_length_mm))
    throw ApiError(400, "'middle_marker_mm' must be 0 (two markers) or between the ends");
  if (min_samples < 10 || min_samples > 1000000) throw ApiError(400, "'min_samples' must be 10..1000000");
  if (!(coverage_target >= 0.05 && coverage_target <= 1.0)) throw ApiError(400, "'coverage_target' must be 0.05..1");
  if (!(timeout_s >= 1.0 && timeout_s <= 3600.0)) throw ApiError(400, "'timeout_s' must be 1..3600");
  try {
    Wand().Check();
    coverage.Check();
    thresholds.Check();
    IntrinsicsRefinementFromName(refine_intrinsics);
  } catch (const std::invalid_argument& e) {
    throw ApiError(400, e.what());
  }
}

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

// The live wanding's options (see wanding_options.h).
#include "service/wanding_options.h"

#include <stdexcept>

#include "calib/wand_bundle_adjustment.h"
#include "service/api_error.h"
#include "service/session_name.h"

namespace mocap::service {

WandGeometry WandingOptions::Wand() const {
  return middle_marker_mm > 0.0 ? WandGeometry::ThreeMarker(wand_length_mm, middle_marker_mm)
                                : WandGeometry::TwoMarker(wand_length_mm);
}

void WandingOptions::Check() const {
  if (mode != kWandingModeWand && mode != kWandingModeSingleMarker)
    throw ApiError(400, "'mode' must be wand or single-marker");
  if (SingleMarker() && middle_marker_mm != 0.0)
    throw ApiError(400, "'middle_marker_mm' is for the wand; a single marker's scale bar has two markers");
  if (SingleMarker() && refine_intrinsics != "none")
    throw ApiError(400, "'refine_intrinsics' must be none for a single marker (its solve holds the intrinsics)");
  if (min_scale_frames < 1 || min_scale_frames > 1000000) throw ApiError(400, "'min_scale_frames' must be 1..1000000");
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

}  // namespace mocap::service

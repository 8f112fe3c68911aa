// Rigid-body pose accuracy against ground truth (eval --bodies-truth/--bodies-result): per body,
// the pivot's position error (mm) and the rotation error (degrees, the angle of
// R_result * R_truth^T) over the frames both files have and the result fitted; gross errors
// (beyond 20 mm or 10 degrees: another body's pose, an identity swap); and availability: the
// share of frames the result fitted among those where at least 3 of the body's markers were seen
// by at least 2 cameras (from the simulated session's visibility; without it, every truth frame).
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "bodies/body_trajectories.h"
#include "io/visibility.h"

namespace mocap {

struct BodyEvalReport {
  struct Body {
    std::string name;
    size_t truth_frames = 0;      // frames of the truth file with this body
    size_t fitted = 0;            // of those, the result fitted (tracked) it
    size_t seen = 0;              // frames with >= 3 markers seen (all truth frames without visibility)
    size_t fitted_when_seen = 0;
    double available_share = 0.0;  // fitted_when_seen / seen
    size_t gross = 0;             // fitted frames beyond 20 mm or 10 degrees
    double p50_mm = 0.0, p95_mm = 0.0, max_mm = 0.0;
    double p50_deg = 0.0, p95_deg = 0.0, max_deg = 0.0;
  };
  std::vector<Body> bodies;  // in the truth file's order of first appearance
  bool visibility_used = false;

  nlohmann::json ToJson() const;
  std::string ToText() const;
};

// `visibility` (may be null) holds one column per truth marker; a body's markers are the
// columns named "<body>:<n>" (sim project --bodies). Throws std::invalid_argument when a truth
// body is missing from the result entirely.
BodyEvalReport EvaluateBodies(const std::vector<BodyPoseRecord>& truth, const std::vector<BodyPoseRecord>& result,
                              const MarkerVisibility* visibility);

}  // namespace mocap

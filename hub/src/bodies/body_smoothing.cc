// A rigid body's orientation refined over neighbouring frames (see body_smoothing.h).
#include "bodies/body_smoothing.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace mocap {

void BodySmoothingOptions::Check() const {
  if (half_window < 0 || half_window > 50) throw std::invalid_argument("body smoothing half window must be 0..50 frames");
  if (degree < 1 || degree > 3) throw std::invalid_argument("body smoothing degree must be 1..3");
  if (!(test_z > 0.0 && test_z < 10.0)) throw std::invalid_argument("body smoothing test quantile must be in (0, 10)");
}

BodySmoothingStats SmoothBodyPoses(const RigidBodyDefinition& body, const std::vector<BodyFrameMarkers>& markers,
                                   std::vector<BodyPose>* poses, const BodySmoothingOptions& options) {
  options.Check();
  if (markers.size() != poses->size()) throw std::invalid_argument("body smoothing: one marker set per pose needed");
  BodySmoothingStats stats;
  const size_t frames = poses->size();
  std::vector<BodyFrameFit> fits(frames);
  double residual_sq = 0.0, residual_dof = 0.0;
  for (size_t f = 0; f < frames; ++f) {
    fits[f] = DescribeFrameFit((*poses)[f], markers[f]);
    residual_sq += fits[f].residual_sq;
    residual_dof += fits[f].residual_dof;
    stats.unchanged += fits[f].usable;
  }
  const double variance = residual_dof > 0.0 ? residual_sq / residual_dof : 0.0;
  stats.noise_mm = std::sqrt(variance);
  if (options.half_window == 0 || !(variance > 1e-12)) return stats;  // noiseless: nothing to average

  std::vector<RotationSample> samples;
  for (size_t f = 0; f < frames; ++f) {
    if (!fits[f].usable) continue;
    // Every frame of the full window; smaller windows use those within |t| <= k.
    const size_t k_max = static_cast<size_t>(options.half_window);
    samples.clear();
    for (size_t j = f >= k_max ? f - k_max : 0; j <= std::min(frames - 1, f + k_max); ++j) {
      if (!fits[j].usable) continue;
      samples.push_back({static_cast<double>(j) - static_cast<double>(f), &fits[j].rotation, &fits[j].information});
    }
    for (int k = options.half_window; k >= 1; --k) {
      const RotationCurveFit curve = FitRotationCurve(samples, fits[f].rotation, k, options.degree, variance, options.test_z);
      if (curve.outcome == RotationCurveFit::kTooFewFrames) break;  // smaller windows hold fewer frames
      if (curve.outcome != RotationCurveFit::kAccepted) continue;
      SetRefinedOrientation(body, fits[f], markers[f], curve.rotation_at_zero, &(*poses)[f]);
      --stats.unchanged;
      ++(k == options.half_window ? stats.refined : stats.shrunk);
      break;
    }
  }
  return stats;
}

}  // namespace mocap

// Option checks and enum converters of the tracking layer.
#include "track/track_options.h"

#include <cstdio>
#include <stdexcept>
#include <string>

namespace mocap {
namespace {

void Require(bool condition, const std::string& message) {
  if (!condition) throw std::invalid_argument(message);
}

// Refuses a value outside [low, high] naming the field, the value and the range.
void RequireRange(const char* field, double value, double low, double high, const char* unit) {
  if (value >= low && value <= high) return;
  char message[200];
  std::snprintf(message, sizeof(message), "%s %g is out of range %g..%g%s", field, value, low, high, unit);
  throw std::invalid_argument(message);
}

}  // namespace

void KalmanOptions::Check() const {
  RequireRange("kalman.acceleration_noise", acceleration_noise, 1.0, 1e7, " (mm/s^2)");
  RequireRange("kalman.measurement_noise_mm", measurement_noise_mm, 1e-3, 1000.0, " (mm)");
  Require(initial_velocity_std > 0.0, "kalman.initial_velocity_std must be > 0");
}

std::string AssignmentMethodToString(AssignmentMethod method) {
  return method == AssignmentMethod::kGreedy ? "greedy" : "optimal";
}

AssignmentMethod AssignmentMethodFromString(const std::string& name) {
  if (name == "greedy") return AssignmentMethod::kGreedy;
  if (name == "optimal") return AssignmentMethod::kOptimal;
  throw std::invalid_argument("unknown assignment '" + name + "' (expected greedy or optimal)");
}

void RigidModelOptions::Check() const {
  Require(max_link_distance_mm > 0.0, "rigid.max_link_distance_mm must be > 0");
  RequireRange("rigid.max_deviation_mm", max_deviation_mm, 0.1, 1000.0, " (mm)");
  RequireRange("rigid.max_std_mm", max_std_mm, 0.1, 1000.0, " (mm)");
  Require(min_samples >= 2, "rigid.min_samples must be >= 2");
  Require(min_links_used >= 1, "rigid.min_links_used must be >= 1");
  Require(max_links_used >= min_links_used, "rigid.max_links_used must be >= min_links_used");
}

void RigidSwapOptions::Check() const {
  Require(min_samples >= 2, "swaps.min_samples must be >= 2");
  Require(link_std_mm > 0.0, "swaps.link_std_mm must be > 0");
  Require(cluster_radius_mm > 0.0, "swaps.cluster_radius_mm must be > 0");
  Require(max_cluster >= 2 && max_cluster <= 6, "swaps.max_cluster must be 2..6");
  Require(min_error_mm >= 0.0, "swaps.min_error_mm must be >= 0");
  Require(improvement > 0.0 && improvement <= 1.0, "swaps.improvement must be in (0, 1]");
}

void TrackerOptions::Check() const {
  Require(rate_hz > 0.0, "tracker.rate_hz must be > 0");
  kalman.Check();
  Require(gate_sigmas > 0.0, "tracker.gate_sigmas must be > 0");
  Require(min_gate_mm > 0.0 && max_gate_mm >= min_gate_mm,
          "tracker gates: need 0 < min_gate_mm <= max_gate_mm");
  Require(birth_frames >= 1, "tracker.birth_frames must be >= 1");
  Require(birth_min_views >= 2 && birth_min_views <= 64,
          "tracker.birth_min_views " + std::to_string(birth_min_views) + " is out of range 2..64");
  Require(two_view_birth_frames >= 1 && two_view_birth_frames <= 1000,
          "tracker.two_view_birth_frames " + std::to_string(two_view_birth_frames) + " is out of range 1..1000");
  Require(max_predicted_s >= 0.0 && coast_s >= 0.0 && reacquire_s >= 0.0 && dropout_hold_s >= 0.0,
          "tracker durations must be >= 0");
  Require(reacquire_gate_mm > 0.0, "tracker.reacquire_gate_mm must be > 0");
  Require(wide_gate_mm > 0.0, "tracker.wide_gate_mm must be > 0");
  rigid.Check();
  swaps.Check();
}

void HindsightSwapOptions::Check() const {
  Require(pair_radius_mm > 0.0, "hindsight_swaps.pair_radius_mm must be > 0");
  Require(improvement > 0.0 && improvement < 1.0, "hindsight_swaps.improvement must be in (0, 1)");
  Require(min_jump_mm >= 0.0, "hindsight_swaps.min_jump_mm must be >= 0");
  Require(rigid_max_sd_mm > 0.0, "hindsight_swaps.rigid_max_sd_mm must be > 0");
  Require(rigid_tolerance_mm > 0.0, "hindsight_swaps.rigid_tolerance_mm must be > 0");
  Require(rigid_weight >= 0.0, "hindsight_swaps.rigid_weight must be >= 0");
}

void GapFillOptions::Check() const {
  Require(max_spline_gap >= 0, "gap_fill.max_spline_gap must be >= 0");
  Require(window_frames >= max_spline_gap + 2, "gap_fill.window_frames must be >= max_spline_gap + 2");
}

}  // namespace mocap

// Procedural motions and markers for the simulated subject.
#include "skeleton/skeleton_sim.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>

#include "skeleton/kinematics.h"

namespace mocap {
namespace {

constexpr double kRad = M_PI / 180.0;

// Range of motion: dof k swings from 0 towards the roomier side of its limits and back
// ((1 - cos) / 2), or both ways about 0 (sin) for the segments calibration takes as zero at the
// start (their 0 is the subject's upright stance).
double RangeAngle(const JointDof& dof, bool middle_of_three, bool about_zero, double f, double phase, double t) {
  const double room = std::max(std::fabs(dof.min_deg), std::fabs(dof.max_deg));
  double amplitude = std::min(0.6 * room, 70.0);
  if (middle_of_three) amplitude = std::min(amplitude, 40.0);
  if (about_zero) {
    amplitude = std::min({amplitude, 0.6 * std::fabs(dof.min_deg), 0.6 * std::fabs(dof.max_deg), 30.0});
    return amplitude * kRad * std::sin(2.0 * M_PI * f * t + phase) - amplitude * kRad * std::sin(phase);
  }
  const double sign = std::fabs(dof.max_deg) >= std::fabs(dof.min_deg) ? 1.0 : -1.0;
  return sign * amplitude * kRad * 0.5 * (1.0 - std::cos(2.0 * M_PI * f * t));
}

double Clamp(const JointDof& dof, double angle) {
  return std::max(dof.min_deg * kRad, std::min(dof.max_deg * kRad, angle));
}

// Gait angles by segment name and axis (degrees), one stride per second; side -1 right, +1 left.
double GaitAngle(const std::string& name, int axis, double t) {
  const double w = 2.0 * M_PI * t;
  const bool left = name.rfind("Left", 0) == 0;
  const bool right = name.rfind("Right", 0) == 0;
  const double phase = right ? M_PI : 0.0;
  const std::string part = left ? name.substr(4) : right ? name.substr(5) : name;
  const double s = std::sin(w + phase), c = std::cos(w + phase);
  if (part == "UpLeg" && axis == 0) return -10.0 - 25.0 * s;
  if (part == "UpLeg" && axis == 2) return 3.0 * c * (right ? -1.0 : 1.0);
  if (part == "Leg" && axis == 0) return 5.0 + 30.0 * std::max(0.0, std::sin(w + phase + 2.2)) + 5.0 * (1.0 + c);
  if (part == "Foot" && axis == 0) return 10.0 * std::sin(w + phase + 1.0);
  if (part == "Arm" && axis == 0) return 20.0 * s;
  if (part == "Arm" && axis == 2) return 8.0 * (right ? -1.0 : 1.0);
  if (part == "ForeArm" && axis == 0) return -25.0 - 10.0 * s;
  if (part == "Spine" && axis == 1) return 5.0 * std::sin(w);
  if (part == "Chest" && axis == 1) return -6.0 * std::sin(w);
  if (part == "Head" && axis == 0) return 5.0;
  return 0.0;
}

}  // namespace

std::string SkeletonSimMotionName(SkeletonSimMotion motion) {
  return motion == SkeletonSimMotion::kGait ? "gait" : "rom";
}

SkeletonSimMotion SkeletonSimMotionFromName(const std::string& name) {
  if (name == "rom") return SkeletonSimMotion::kRangeOfMotion;
  if (name == "gait") return SkeletonSimMotion::kGait;
  throw std::invalid_argument("motion: \"" + name + "\" is not rom or gait");
}

void SkeletonSimOptions::Check() const {
  if (!(rate_hz >= 1.0 && rate_hz <= 2000.0)) throw std::invalid_argument("rate_hz: " + std::to_string(rate_hz) + " not in 1..2000");
  if (!(duration_s > 0.0 && duration_s <= 600.0))
    throw std::invalid_argument("duration_s: " + std::to_string(duration_s) + " not in (0, 600]");
  if (!(scale >= 0.5 && scale <= 2.0)) throw std::invalid_argument("scale: " + std::to_string(scale) + " not in 0.5..2");
  if (!(variation >= 0.0 && variation <= 0.3))
    throw std::invalid_argument("variation: " + std::to_string(variation) + " not in 0..0.3");
  if (!(marker_shift_mm >= 0.0 && marker_shift_mm <= 50.0))
    throw std::invalid_argument("marker_shift_mm: " + std::to_string(marker_shift_mm) + " not in 0..50");
  if (!(wobble_mm >= 0.0 && wobble_mm <= 30.0))
    throw std::invalid_argument("wobble_mm: " + std::to_string(wobble_mm) + " not in 0..30");
}

SkeletonSimulation SimulateSkeleton(const Skeleton& skeleton_template, const SkeletonSimOptions& options) {
  options.Check();
  skeleton_template.Check();
  std::mt19937_64 rng(options.seed);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  SkeletonSimulation sim;
  sim.subject = skeleton_template;
  sim.subject.calibrated = true;
  for (SkeletonSegment& s : sim.subject.segments) {
    s.offset *= options.scale * (1.0 + options.variation * unit(rng));
    s.end *= options.scale;
  }
  for (SkeletonMarker& m : sim.subject.markers)
    m.offset = m.offset * options.scale +
               options.marker_shift_mm * Eigen::Vector3d(unit(rng), unit(rng), unit(rng)) / std::sqrt(3.0);
  const Skeleton& subject = sim.subject;

  // Per dof: frequency and phase (range of motion), per marker: wobble direction, frequency, phase.
  const size_t n = subject.NumPoseParameters();
  std::vector<double> frequency(n), phase(n);
  for (size_t k = 0; k < n; ++k) {
    frequency[k] = 0.5 + 0.8 * (0.5 + 0.5 * unit(rng));
    phase[k] = M_PI * unit(rng);
  }
  std::vector<Eigen::Vector3d> wobble_dir(subject.markers.size());
  std::vector<double> wobble_f(subject.markers.size()), wobble_phase(subject.markers.size());
  for (size_t m = 0; m < subject.markers.size(); ++m) {
    wobble_dir[m] = Eigen::Vector3d(unit(rng), unit(rng), unit(rng)).normalized();
    wobble_f[m] = 2.0 + 3.0 * (0.5 + 0.5 * unit(rng));
    wobble_phase[m] = M_PI * unit(rng);
  }
  // Standing height of the root: the lowest marker of the rest pose touches the floor.
  std::vector<double> rest(n, 0.0);
  SkeletonPoseState state;
  ForwardKinematics(subject, rest.data(), nullptr, &state);
  double lowest = 0.0;
  for (const SkeletonMarker& m : subject.markers) lowest = std::min(lowest, MarkerInSkeleton(state, m.segment, m.offset).y());
  const double standing = -lowest + 10.0;

  const size_t frames = static_cast<size_t>(std::floor(options.duration_s * options.rate_hz + 1e-9));
  sim.motion.rate_hz = options.rate_hz;
  sim.markers.rate_hz = options.rate_hz;
  for (const SkeletonMarker& m : subject.markers) sim.markers.names.push_back(m.name);
  for (size_t f = 0; f < frames; ++f) {
    const double t = static_cast<double>(f) / options.rate_hz;
    std::vector<double> pose(n, 0.0);
    size_t k = 3;
    for (size_t g = 0; g < subject.NumSegments(); ++g) {
      const SkeletonSegment& s = subject.segments[g];
      for (size_t d = 0; d < s.dofs.size(); ++d, ++k) {
        if (options.motion == SkeletonSimMotion::kGait) {
          pose[k] = g == 0 ? 0.0 : Clamp(s.dofs[d], GaitAngle(s.name, s.dofs[d].axis, t) * kRad);
        } else if (g == 0) {
          // The root: a slow turn about the vertical, small tilts about zero.
          pose[k] = s.dofs[d].axis == 1 ? 0.6 * std::sin(2.0 * M_PI * 0.25 * t)
                                        : 8.0 * kRad * std::sin(2.0 * M_PI * frequency[k] * t);
        } else {
          pose[k] = Clamp(s.dofs[d], RangeAngle(s.dofs[d], s.dofs.size() == 3 && d == 1, s.reference_zero,
                                                frequency[k], phase[k], t));
        }
      }
    }
    if (options.motion == SkeletonSimMotion::kGait) {
      pose[0] = 0.0;
      pose[1] = standing - 20.0 + 15.0 * std::cos(4.0 * M_PI * t);
      pose[2] = 1200.0 * t - 1200.0 * options.duration_s / 2.0;
      pose[4] = 3.0 * kRad * std::sin(4.0 * M_PI * t);
    } else {
      pose[0] = 30.0 * std::sin(2.0 * M_PI * 0.3 * t);
      pose[1] = standing + 20.0 * std::sin(2.0 * M_PI * 0.7 * t);
      pose[2] = 30.0 * std::sin(2.0 * M_PI * 0.2 * t);
    }
    ForwardKinematics(subject, pose.data(), nullptr, &state);
    const size_t row = sim.markers.AddFrame(f);
    for (size_t m = 0; m < subject.markers.size(); ++m) {
      const SkeletonMarker& marker = subject.markers[m];
      const Eigen::Vector3d local =
          marker.offset + options.wobble_mm * std::sin(2.0 * M_PI * wobble_f[m] * t + wobble_phase[m]) * wobble_dir[m];
      sim.markers.At(row, m) = MarkerInSkeleton(state, marker.segment, local);
    }
    sim.motion.poses.push_back(pose);
  }
  return sim;
}

}  // namespace mocap

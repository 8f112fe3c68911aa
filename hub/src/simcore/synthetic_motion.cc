// Rest pose on a body-sized cylinder, then a heading turn, a circular walk and limb swings.
#include "simcore/synthetic_motion.h"

#include <cmath>
#include <random>
#include <stdexcept>
#include <vector>

namespace mocap {

namespace {
constexpr double kPi = 3.14159265358979323846;
}  // namespace

void SyntheticMotionOptions::Check() const {
  if (markers < 1 || markers > 500) throw std::invalid_argument("synthetic motion: markers must be 1..500");
  if (frames < 1) throw std::invalid_argument("synthetic motion: frames must be >= 1");
  if (!(rate_hz > 0.0)) throw std::invalid_argument("synthetic motion: rate must be positive");
  if (up_axis < 0 || up_axis > 2) throw std::invalid_argument("synthetic motion: up axis must be 0..2");
}

MarkerTrajectories MakeSyntheticMotion(const SyntheticMotionOptions& options) {
  options.Check();
  std::mt19937_64 rng(options.seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  // Rest pose in body coordinates (x forward, y left, z up): markers on a cylinder of radius
  // 150-250 mm between 80 mm and 1750 mm, kept apart like real marker sets.
  std::vector<Eigen::Vector3d> rest;
  std::vector<double> swing_phase;
  int attempts = 0;
  while (static_cast<int>(rest.size()) < options.markers) {
    if (++attempts > 100000) throw std::invalid_argument("synthetic motion: cannot place markers that far apart");
    const double angle = 2.0 * kPi * unit(rng);
    const double radius = 150.0 + 100.0 * unit(rng);
    const Eigen::Vector3d candidate(radius * std::cos(angle), radius * std::sin(angle), 80.0 + 1670.0 * unit(rng));
    bool apart = true;
    for (const Eigen::Vector3d& other : rest) apart = apart && (other - candidate).norm() >= options.min_separation_mm;
    if (!apart) continue;
    rest.push_back(candidate);
    swing_phase.push_back(candidate.y() > 0 ? 0.0 : kPi);
  }

  MarkerTrajectories motion;
  motion.rate_hz = options.rate_hz;
  for (int m = 0; m < options.markers; ++m) motion.names.push_back(DefaultMarkerName(m));
  // Map body (forward, left, up) onto the world axes so that body up is the requested axis.
  const int up = options.up_axis;
  const int a = (up + 1) % 3, b = (up + 2) % 3;
  for (int f = 0; f < options.frames; ++f) {
    const size_t index = motion.AddFrame(options.first_frame + static_cast<uint64_t>(f));
    const double t = f / options.rate_hz;
    const double heading = 0.5 * t;  // walking a circle of 800 mm radius at 0.4 m/s
    const Eigen::Vector2d center(800.0 * std::cos(heading), 800.0 * std::sin(heading));
    const double gait = 2.0 * kPi * 0.9 * t;
    for (int m = 0; m < options.markers; ++m) {
      Eigen::Vector3d body = rest[m];
      // Limbs (below the hips, or out at the sides) swing fore and aft; the trunk bobs.
      const double swing = body.z() < 900.0 ? 200.0 * (1.0 - body.z() / 900.0) : 0.0;
      body.x() += swing * std::sin(gait + swing_phase[m]);
      body.z() += 25.0 * std::sin(2.0 * gait);
      const double c = std::cos(heading + kPi / 2.0), s = std::sin(heading + kPi / 2.0);
      Eigen::Vector3d world;
      world[a] = center.x() + c * body.x() - s * body.y();
      world[b] = center.y() + s * body.x() + c * body.y();
      world[up] = body.z();
      motion.At(index, m) = world;
    }
  }
  return motion;
}

}  // namespace mocap

// Rigid bodies flying around a motion's subject (see body_scene.h).
#include "sim/body_scene.h"

#include <cmath>
#include <random>
#include <stdexcept>

#include <Eigen/Geometry>

namespace mocap {
namespace {

constexpr double kPi = 3.14159265358979323846;

}  // namespace

void BodySceneOptions::Check() const {
  if (!(min_radius_mm > 0.0 && max_radius_mm >= min_radius_mm && max_radius_mm < 1e5))
    throw std::invalid_argument("body paths: need 0 < min radius <= max radius");
  if (!(speed_rad_s >= 0.0 && speed_rad_s < 100.0) || !(spin_deg_s >= 0.0 && spin_deg_s < 1e4))
    throw std::invalid_argument("body paths: speed and spin out of range");
  if (up_axis < -1 || up_axis > 2) throw std::invalid_argument("up axis must be 0, 1, 2 or -1");
}

BodyScene AddRigidBodies(const MarkerTrajectories& motion, const std::vector<RigidBodyDefinition>& bodies,
                         const BodySceneOptions& options) {
  options.Check();
  if (motion.NumFrames() == 0 || !(motion.rate_hz > 0.0)) throw std::invalid_argument("the motion has no frames or rate");
  if (bodies.empty()) throw std::invalid_argument("no rigid bodies to add");
  const int up = options.up_axis >= 0 ? options.up_axis : DetectUpAxis(motion);
  if (up < 0) throw std::invalid_argument("cannot tell the motion's up axis");
  const int h1 = (up + 1) % 3, h2 = (up + 2) % 3;  // the horizontal axes

  BodyScene out;
  MarkerTrajectories& scene = out.scene;
  scene.rate_hz = motion.rate_hz;
  scene.names = motion.names;
  for (const RigidBodyDefinition& b : bodies)
    for (size_t m = 0; m < b.markers.size(); ++m) scene.names.push_back(b.name + ":" + std::to_string(m + 1));

  std::mt19937_64 random(options.seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  struct Path {
    double phase, height, reverse_s, axis_phase;
    Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  };
  std::vector<Path> paths(bodies.size());
  for (size_t b = 0; b < bodies.size(); ++b) {
    paths[b].phase = 2.0 * kPi * static_cast<double>(b) / static_cast<double>(bodies.size()) + 0.3 * unit(random);
    paths[b].height = 150.0 * (static_cast<double>(b) - 0.5 * static_cast<double>(bodies.size() - 1));
    paths[b].reverse_s = 1.5 + 1.5 * unit(random);
    paths[b].axis_phase = 2.0 * kPi * unit(random);
  }
  const double dt = 1.0 / motion.rate_hz;
  Eigen::Vector3d last_centre = Eigen::Vector3d::Zero();
  for (size_t f = 0; f < motion.NumFrames(); ++f) {
    const size_t row = scene.AddFrame(motion.frame_numbers[f]);
    Eigen::Vector3d centre = Eigen::Vector3d::Zero();
    size_t n = 0;
    for (size_t m = 0; m < motion.NumMarkers(); ++m) {
      if (!motion.Has(f, m)) continue;
      scene.At(row, m) = motion.At(f, m);
      centre += motion.At(f, m), ++n;
    }
    centre = n ? Eigen::Vector3d(centre / static_cast<double>(n)) : last_centre;
    last_centre = centre;
    const double t = static_cast<double>(f) * dt;
    BodyPoseRow poses;
    poses.frame_number = motion.frame_numbers[f];
    size_t column = motion.NumMarkers();
    for (size_t b = 0; b < bodies.size(); ++b) {
      Path& path = paths[b];
      // Along the circle and back: the direction flips every reverse_s seconds (a fast turn).
      const double u = std::fmod(t, 2.0 * path.reverse_s);
      // Neighbours go opposite ways, so that they meet (at the same radius, 150 mm apart in height).
      const double direction = b % 2 == 0 ? 1.0 : -1.0;
      const double angle =
          path.phase + direction * options.speed_rad_s * (u < path.reverse_s ? u : 2.0 * path.reverse_s - u);
      const double radius = options.min_radius_mm + (options.max_radius_mm - options.min_radius_mm) *
                                                         (0.5 + 0.5 * std::sin(1.7 * t));
      Eigen::Vector3d position = centre;
      position[h1] += radius * std::cos(angle);
      position[h2] += radius * std::sin(angle);
      position[up] += path.height + 150.0 * std::sin(1.3 * t + path.phase);
      // Spin about a wandering axis.
      const Eigen::Vector3d axis =
          Eigen::Vector3d(std::sin(0.7 * t + path.axis_phase), std::cos(0.9 * t + path.axis_phase), 0.6).normalized();
      if (f > 0) path.rotation = Eigen::AngleAxisd(options.spin_deg_s * kPi / 180.0 * dt, axis).toRotationMatrix() * path.rotation;
      const RigidBodyDefinition& body = bodies[b];
      BodyPose pose;
      pose.tracked = true;
      pose.orientation = Eigen::Quaterniond(path.rotation).normalized();
      pose.position = position;
      pose.pivot = path.rotation * body.pivot + position;
      pose.markers = body.markers.size();
      for (const Eigen::Vector3d& m : body.markers) scene.At(row, column++) = path.rotation * m + position;
      poses.poses.push_back(pose);
    }
    out.poses.push_back(std::move(poses));
  }
  return out;
}

}  // namespace mocap

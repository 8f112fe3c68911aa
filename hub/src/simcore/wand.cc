// Wand waving: the centre travels from one random spot of the volume to the next with a smooth
// velocity; the axis turns at a random, smoothly changing angular velocity (Ornstein-Uhlenbeck).
#include "simcore/wand.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Dense>
#include <Eigen/Geometry>

namespace mocap {
namespace {

// True when the camera images the point: in front, inside the image, and not folded back by
// the lens polynomial (a pixel that undistorts to another ray is no real observation).
bool Sees(const Camera& camera, const Eigen::Vector3d& point) {
  Eigen::Vector2d pixel;
  if (!camera.ProjectToPixel(point, &pixel) || !camera.InImage(pixel)) return false;
  const Eigen::Vector3d in_cam = camera.PointInCamera(point);
  return (camera.UndistortPixel(pixel) - in_cam.head<2>() / in_cam.z()).norm() < 1e-6;
}

// Least-squares point closest to every camera's optical axis.
Eigen::Vector3d AimPoint(const Rig& rig) {
  Eigen::Matrix3d normal = Eigen::Matrix3d::Zero();
  Eigen::Vector3d rhs = Eigen::Vector3d::Zero();
  for (const Camera& camera : rig.cameras) {
    const Eigen::Vector3d d = camera.rotation.row(2).transpose();
    const Eigen::Matrix3d projector = Eigen::Matrix3d::Identity() - d * d.transpose();
    normal += projector;
    rhs += projector * camera.CenterInWorld();
  }
  return normal.ldlt().solve(rhs);
}

}  // namespace

void WandMotionOptions::Check() const {
  if (!(wand_length_mm >= 50.0 && wand_length_mm <= 5000.0)) {
    throw std::invalid_argument("--wand-length must be 50..5000 mm");
  }
  if (middle_marker_mm != 0.0 && !(middle_marker_mm > 0.1 * wand_length_mm && middle_marker_mm < 0.9 * wand_length_mm)) {
    throw std::invalid_argument("--middle-marker must lie between 10% and 90% of the wand length");
  }
  if (frames < 1 || frames > 10000000) throw std::invalid_argument("--frames must be 1..10000000");
  if (!(rate_hz > 0.0 && rate_hz <= 10000.0)) throw std::invalid_argument("--rate must be in (0, 10000] Hz");
  if (!(speed_mm_s > 0.0 && speed_mm_s < 20000.0)) throw std::invalid_argument("--speed must be in (0, 20000) mm/s");
  if (!(turn_deg_s >= 0.0 && turn_deg_s < 3600.0)) throw std::invalid_argument("--turn must be in [0, 3600) deg/s");
  if (min_cameras != 0 && min_cameras < 2) throw std::invalid_argument("--min-cameras must be 0 (half the rig) or >= 2");
  if (up_axis < -1 || up_axis > 2) throw std::invalid_argument("up axis must be x, y, z or auto");
  if (single_marker_frames < 0 || single_marker_frames > frames)
    throw std::invalid_argument("--single-marker-frames must be 0..--frames");
  if (lframe_frames < 0) throw std::invalid_argument("--lframe-frames must be >= 0");
  if (lframe_frames > 0 && lframe_markers.size() < 3) {
    throw std::invalid_argument("an L-frame needs at least 3 markers");
  }
}

MotionVolume WandVolume(const Rig& rig, int min_cameras, int up_axis) {
  if (rig.cameras.size() < 2) throw std::runtime_error("the rig needs at least two cameras");
  if (min_cameras == 0) min_cameras = std::max(2, static_cast<int>(rig.cameras.size() / 2));
  const Eigen::Vector3d aim = AimPoint(rig);
  Eigen::Vector3d mean_forward = Eigen::Vector3d::Zero();
  double reach = 0.0;
  for (const Camera& camera : rig.cameras) {
    mean_forward += camera.rotation.row(2).transpose();
    reach += (camera.CenterInWorld() - aim).norm();
  }
  reach /= static_cast<double>(rig.cameras.size());
  MotionVolume volume;
  if (up_axis < 0) {
    // Cameras on a truss look down: up is the world axis most opposed to their mean view.
    mean_forward.cwiseAbs().maxCoeff(&up_axis);
  }
  volume.up_axis = up_axis;
  Eigen::Vector3d up = Eigen::Vector3d::Unit(up_axis);
  if (mean_forward.dot(up) > 0.0) up = -up;
  double height = 0.0;
  for (const Camera& camera : rig.cameras) height += (camera.CenterInWorld() - aim).dot(up);
  height = std::max(height / static_cast<double>(rig.cameras.size()), 0.1 * reach);

  const int steps = 32;
  std::vector<Eigen::Vector3d> seen_points;
  for (int i = 0; i <= steps; ++i) {
    for (int j = 0; j <= steps; ++j) {
      for (int k = 0; k <= steps; ++k) {
        const Eigen::Vector3d point =
            aim + reach * (Eigen::Vector3d(i, j, k) * (2.0 / steps) - Eigen::Vector3d::Ones());
        if (std::abs((point - aim).dot(up)) > 0.6 * height) continue;
        int seen = 0;
        for (const Camera& camera : rig.cameras) seen += Sees(camera, point) ? 1 : 0;
        if (seen >= min_cameras) seen_points.push_back(point);
      }
    }
  }
  if (seen_points.empty()) {
    throw std::runtime_error("no point is seen by " + std::to_string(min_cameras) +
                             " cameras of the rig: the cameras do not share a volume");
  }
  // Per-axis 5th and 95th percentiles: a few far corners seen by cameras across the room must
  // not stretch the box over regions most cameras miss.
  for (int a = 0; a < 3; ++a) {
    std::vector<double> values;
    for (const Eigen::Vector3d& point : seen_points) values.push_back(point(a));
    std::sort(values.begin(), values.end());
    volume.min(a) = values[static_cast<size_t>(0.05 * (values.size() - 1))];
    volume.max(a) = values[static_cast<size_t>(0.95 * (values.size() - 1))];
  }
  return volume;
}

MarkerTrajectories MakeWandMotion(const Rig& rig, const WandMotionOptions& options) {
  options.Check();
  const MotionVolume volume = WandVolume(rig, options.min_cameras, options.up_axis);
  std::mt19937_64 rng(options.seed);
  std::normal_distribution<double> gauss(0.0, 1.0);
  std::uniform_real_distribution<double> unit(0.0, 1.0);

  MarkerTrajectories motion;
  motion.rate_hz = options.rate_hz;
  const bool three = options.middle_marker_mm > 0.0;
  motion.names = three ? std::vector<std::string>{"W1", "W2", "W3"} : std::vector<std::string>{"W1", "W2"};
  const size_t wand_markers = motion.names.size();
  for (size_t i = 0; i < (options.lframe_frames > 0 ? options.lframe_markers.size() : 0); ++i) {
    motion.names.push_back("L" + std::to_string(i + 1));
  }
  std::vector<double> offsets = {-0.5 * options.wand_length_mm};
  if (three) offsets.push_back(-0.5 * options.wand_length_mm + options.middle_marker_mm);
  offsets.push_back(0.5 * options.wand_length_mm);

  // Keep the whole wand inside the volume where the volume allows it.
  const Eigen::Vector3d size = volume.max - volume.min;
  const Eigen::Vector3d inset = (0.5 * size).cwiseMin(Eigen::Vector3d::Constant(0.3 * options.wand_length_mm));
  const Eigen::Vector3d low = volume.min + inset;
  const Eigen::Vector3d high = volume.max - inset;

  const double dt = 1.0 / options.rate_hz;
  // The hand heads for one random spot of the volume after another; its velocity follows the
  // heading with a lag, so the path is smooth and still sweeps the whole volume in a few legs.
  const double lag_s = 0.3;
  const double follow = 1.0 - std::exp(-dt / lag_s);
  const double correlation_s = 0.5;  // how long a sense of turning persists
  const double decay = std::exp(-dt / correlation_s);
  const double kick = std::sqrt(1.0 - decay * decay);
  auto random_spot = [&]() {
    return Eigen::Vector3d(low + (high - low).cwiseProduct(Eigen::Vector3d(unit(rng), unit(rng), unit(rng))));
  };
  Eigen::Vector3d centre = random_spot();
  Eigen::Vector3d target = random_spot();
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();
  Eigen::Vector3d axis = Eigen::Vector3d(gauss(rng), gauss(rng), gauss(rng)).normalized();
  const double turn = options.turn_deg_s * M_PI / 180.0;
  Eigen::Vector3d spin = turn / std::sqrt(3.0) * Eigen::Vector3d(gauss(rng), gauss(rng), gauss(rng));
  const double arrive_mm = 0.1 * size.minCoeff() + 50.0;
  for (int f = 0; f < options.frames; ++f) {
    const size_t row = motion.AddFrame(static_cast<uint64_t>(f));
    for (size_t m = 0; m < wand_markers; ++m) {
      const bool hidden = m > 0 && f < options.single_marker_frames;
      motion.At(row, m) = hidden ? Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN())
                                 : Eigen::Vector3d(centre + offsets[m] * axis);
    }
    if ((target - centre).norm() < arrive_mm) target = random_spot();
    const Eigen::Vector3d wanted = options.speed_mm_s * (target - centre).normalized();
    velocity += follow * (wanted - velocity);
    centre = (centre + velocity * dt).cwiseMax(low).cwiseMin(high);
    spin = decay * spin + kick * turn / std::sqrt(3.0) * Eigen::Vector3d(gauss(rng), gauss(rng), gauss(rng));
    if (spin.norm() > 0.0) axis = Eigen::AngleAxisd(spin.norm() * dt, spin.normalized()) * axis;
    axis.normalize();
  }
  for (int f = 0; f < options.lframe_frames; ++f) {
    const size_t row = motion.AddFrame(static_cast<uint64_t>(options.frames + f));
    for (size_t i = 0; i < options.lframe_markers.size(); ++i) {
      motion.At(row, wand_markers + i) = options.lframe_markers[i];
    }
  }
  return motion;
}

}  // namespace mocap

// Ring placement: distance from the field of view so the whole volume fits every camera.
#include "simcore/ring_rig.h"

#include <cmath>
#include <random>
#include <stdexcept>

#include <Eigen/Geometry>

#include "simcore/look_at.h"

namespace mocap {
namespace {

constexpr double kPi = 3.14159265358979323846;

}  // namespace

void RingRigOptions::Check() const {
  if (cameras < 2 || cameras > 256) throw std::invalid_argument("--cameras must be 2..256");
  if (width < 16 || height < 16 || width > 16384 || height > 16384) {
    throw std::invalid_argument("--width and --height must be 16..16384");
  }
  if (!(fov_deg >= 10.0 && fov_deg <= 150.0)) throw std::invalid_argument("--fov-deg must be 10..150");
  if (!(mount_above_mm >= 0.0 && mount_above_mm < 1e5)) throw std::invalid_argument("mount height must be 0..1e5 mm");
  if (!(margin >= 1.0 && margin <= 10.0)) throw std::invalid_argument("margin must be 1..10");
}

Rig MakeRingRig(const MotionVolume& volume, const RingRigOptions& options) {
  options.Check();
  std::mt19937_64 rng(options.seed);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  const auto jitter = [&](double amplitude) { return options.jitter ? amplitude * unit(rng) : 0.0; };

  const Eigen::Vector3d up = volume.Up();
  const Eigen::Vector3d center = volume.Center();
  // Two horizontal axes completing a right-handed frame with up.
  const Eigen::Vector3d east = Eigen::Vector3d::Unit((volume.up_axis + 1) % 3);
  const Eigen::Vector3d north = up.cross(east);

  const double focal = 0.5 * options.width / std::tan(0.5 * options.fov_deg * kPi / 180.0);
  const double half_fov_narrow = std::atan(0.5 * std::min(options.width, options.height) / focal);
  // The volume's bounding sphere must fit the narrower field of view.
  const double radius = std::max(0.5 * (volume.max - volume.min).norm(), 100.0);
  const double distance = options.margin * radius / std::sin(half_fov_narrow);
  const double top = (volume.max - center).dot(up);
  const double elevation = std::min(top + options.mount_above_mm, 0.8 * distance);
  const double ring_radius = std::sqrt(distance * distance - elevation * elevation);

  Rig rig;
  for (int i = 0; i < options.cameras; ++i) {
    Camera camera;
    camera.id = static_cast<uint32_t>(i + 1);
    CameraIntrinsics& in = camera.intrinsics;
    in.width = options.width;
    in.height = options.height;
    in.fx = focal * (1.0 + jitter(0.01));
    in.fy = in.fx * (1.0 + jitter(0.001));
    in.cx = 0.5 * options.width + jitter(0.005 * options.width);
    in.cy = 0.5 * options.height + jitter(0.005 * options.height);
    if (options.lens_distortion) {
      // Typical of the M12 wide-angle lenses on small global-shutter cameras; every camera
      // differs so a calibration cannot get away with one shared lens model.
      in.distortion = {-0.20 + 0.05 * unit(rng), 0.08 + 0.03 * unit(rng), 0.001 * unit(rng),
                       0.001 * unit(rng), -0.01 + 0.01 * unit(rng)};
    }
    const double angle = 2.0 * kPi * i / options.cameras + jitter(5.0 * kPi / 180.0);
    const Eigen::Vector3d position = center + ring_radius * (std::cos(angle) * east + std::sin(angle) * north) +
                                     (elevation + jitter(100.0)) * up;
    const Eigen::Vector3d target = center + Eigen::Vector3d(jitter(50.0), jitter(50.0), jitter(50.0));
    AimCamera(position, target, up, &camera);
    rig.cameras.push_back(camera);
  }
  return rig;
}

}  // namespace mocap

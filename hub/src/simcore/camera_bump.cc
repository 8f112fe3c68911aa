// Bumps of simulated cameras.
#include "simcore/camera_bump.h"

#include <cmath>
#include <random>
#include <stdexcept>

#include <Eigen/Geometry>

namespace mocap {
namespace {

double ParseNumber(const std::string& field, const std::string& what, const std::string& text) {
  size_t used = 0;
  double value = 0.0;
  try {
    value = std::stod(field, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || used != field.size() || !std::isfinite(value))
    throw std::invalid_argument("bump '" + text + "': " + what + " is not a number");
  return value;
}

Eigen::Vector3d RandomUnitVector(std::mt19937_64* rng) {
  std::normal_distribution<double> normal(0.0, 1.0);
  for (int attempt = 0; attempt < 100; ++attempt) {
    const Eigen::Vector3d v(normal(*rng), normal(*rng), normal(*rng));
    if (v.norm() > 1e-6) return v.normalized();
  }
  return Eigen::Vector3d::UnitX();
}

}  // namespace

CameraBump ParseCameraBump(const std::string& text) {
  const size_t first = text.find(':');
  const size_t second = first == std::string::npos ? std::string::npos : text.find(':', first + 1);
  if (second == std::string::npos || text.find(':', second + 1) != std::string::npos)
    throw std::invalid_argument("bump '" + text + "': expected CAM:DEG:MM, e.g. 3:0.5:5");
  const double id = ParseNumber(text.substr(0, first), "the camera id", text);
  if (id < 1 || id > 4294967295.0 || id != std::floor(id))
    throw std::invalid_argument("bump '" + text + "': the camera id must be a positive integer");
  CameraBump bump;
  bump.camera_id = static_cast<uint32_t>(id);
  bump.degrees = ParseNumber(text.substr(first + 1, second - first - 1), "the angle (degrees)", text);
  bump.mm = ParseNumber(text.substr(second + 1), "the displacement (mm)", text);
  if (std::abs(bump.degrees) > 180.0)
    throw std::invalid_argument("bump '" + text + "': the angle must be within [-180, 180] degrees");
  if (std::abs(bump.mm) > 1e5) throw std::invalid_argument("bump '" + text + "': the displacement must be below 100 m");
  return bump;
}

void ApplyCameraBump(const CameraBump& bump, Rig* rig) {
  Camera* camera = nullptr;
  for (Camera& c : rig->cameras) {
    if (c.id == bump.camera_id) camera = &c;
  }
  if (camera == nullptr)
    throw std::invalid_argument("bump: the rig has no camera " + std::to_string(bump.camera_id));
  std::mt19937_64 rng(bump.seed ^ (0x9e3779b97f4a7c15ull * (bump.camera_id + 1)));
  const Eigen::Vector3d axis = RandomUnitVector(&rng);
  const Eigen::Vector3d direction = RandomUnitVector(&rng);
  const Eigen::Vector3d centre = camera->CenterInWorld() + bump.mm * direction;
  // The camera turns in its own frame: new cam_from_world = delta * old rotation.
  const Eigen::Matrix3d delta = Eigen::AngleAxisd(bump.degrees * M_PI / 180.0, axis).toRotationMatrix();
  camera->rotation = delta * camera->rotation;
  camera->translation = -camera->rotation * centre;
}

PoseChange ComparePoses(const Camera& a, const Camera& b) {
  PoseChange change;
  change.centre_mm = (a.CenterInWorld() - b.CenterInWorld()).norm();
  const Eigen::AngleAxisd relative(a.rotation * b.rotation.transpose());
  change.rotation_deg = std::abs(relative.angle()) * 180.0 / M_PI;
  return change;
}

}  // namespace mocap

// Mean and spread of repeated calibrations, each rigidly aligned onto the reference first.
#include "eval/calibration_repeatability.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include <Eigen/Geometry>
#include <Eigen/SVD>

#include "geometry/rigid_fit.h"

namespace mocap {
namespace {

constexpr double kDeg = 180.0 / M_PI;

// world_from_cam rotation and centre of one camera of one calibration, in the reference world.
struct Placement {
  Eigen::Matrix3d world_from_cam;
  Eigen::Vector3d centre;
};

Eigen::Matrix3d NearestRotation(const Eigen::Matrix3d& m) {
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(m, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d d = Eigen::Matrix3d::Identity();
  d(2, 2) = (svd.matrixU() * svd.matrixV().transpose()).determinant() < 0.0 ? -1.0 : 1.0;
  return svd.matrixU() * d * svd.matrixV().transpose();
}

}  // namespace

CalibrationRepeatability EvaluateRepeatability(const std::vector<Rig>& calibrations, const Rig* truth, bool align) {
  if (calibrations.size() < 2)
    throw std::invalid_argument("repeatability needs at least 2 calibrations, got " +
                                std::to_string(calibrations.size()));
  const Rig& reference = truth != nullptr ? *truth : calibrations.front();
  CalibrationRepeatability result;
  result.calibrations = calibrations.size();
  result.aligned = align;
  result.against_truth = truth != nullptr;
  std::vector<std::vector<Placement>> placements(reference.cameras.size());
  for (size_t k = 0; k < calibrations.size(); ++k) {
    const Rig& rig = calibrations[k];
    SimilarityTransform reference_from_rig;
    if (align) {
      std::vector<Eigen::Vector3d> source, target;
      for (const Camera& camera : reference.cameras) {
        const Camera* found = rig.Find(camera.id);
        if (found == nullptr) continue;
        source.push_back(found->CenterInWorld());
        target.push_back(camera.CenterInWorld());
      }
      if (source.size() < 3)
        throw std::invalid_argument("calibration " + std::to_string(k + 1) + " shares " +
                                    std::to_string(source.size()) +
                                    " cameras with the reference; aligning needs at least 3");
      reference_from_rig = FitRigid(source, target);
    }
    for (size_t c = 0; c < reference.cameras.size(); ++c) {
      const Camera* found = rig.Find(reference.cameras[c].id);
      if (found == nullptr) continue;
      placements[c].push_back({reference_from_rig.rotation * found->rotation.transpose(),
                               reference_from_rig.Apply(found->CenterInWorld())});
    }
  }
  for (size_t c = 0; c < reference.cameras.size(); ++c) {
    const std::vector<Placement>& p = placements[c];
    if (p.size() < 2) continue;
    const double n = static_cast<double>(p.size());
    CameraRepeatability camera;
    camera.id = reference.cameras[c].id;
    camera.calibrations = p.size();
    Eigen::Matrix3d rotation_sum = Eigen::Matrix3d::Zero();
    for (const Placement& q : p) {
      camera.centre_mean_mm += q.centre / n;
      rotation_sum += q.world_from_cam;
    }
    const Eigen::Matrix3d mean_rotation = NearestRotation(rotation_sum);
    Eigen::Vector3d centre_sq = Eigen::Vector3d::Zero(), rotation_sq = Eigen::Vector3d::Zero();
    double spread_sq = 0.0, angle_sq = 0.0;
    for (const Placement& q : p) {
      const Eigen::Vector3d d = q.centre - camera.centre_mean_mm;
      centre_sq += d.cwiseProduct(d);
      spread_sq += d.squaredNorm();
      // Deviation in the camera's own axes: mean^-1 * this.
      const Eigen::AngleAxisd deviation(mean_rotation.transpose() * q.world_from_cam);
      const Eigen::Vector3d v = deviation.angle() * deviation.axis() * kDeg;
      rotation_sq += v.cwiseProduct(v);
      angle_sq += v.squaredNorm();
    }
    camera.centre_std_mm = (centre_sq / (n - 1.0)).cwiseSqrt();
    camera.rotation_std_deg = (rotation_sq / (n - 1.0)).cwiseSqrt();
    camera.centre_spread_mm = std::sqrt(spread_sq / n);
    camera.rotation_spread_deg = std::sqrt(angle_sq / n);
    camera.euler_mean_deg = mean_rotation.eulerAngles(0, 1, 2) * kDeg;
    if (truth != nullptr) {
      const Camera& t = truth->cameras[c];
      camera.centre_bias_mm = (camera.centre_mean_mm - t.CenterInWorld()).norm();
      camera.rotation_bias_deg = Eigen::AngleAxisd(mean_rotation.transpose() * t.rotation.transpose()).angle() * kDeg;
    }
    result.centre_spread_max_mm = std::max(result.centre_spread_max_mm, camera.centre_spread_mm);
    result.rotation_spread_max_deg = std::max(result.rotation_spread_max_deg, camera.rotation_spread_deg);
    result.cameras.push_back(camera);
  }
  if (result.cameras.empty()) throw std::invalid_argument("no camera of the reference appears in two calibrations");
  return result;
}

}  // namespace mocap

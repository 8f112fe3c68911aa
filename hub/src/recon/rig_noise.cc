// Centroid noise: from the calibration, measured from residuals, and the gates it sets.
#include "recon/rig_noise.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Dense>

namespace mocap {
namespace {

// Lower quartile of a chi-square variable of k degrees of freedom over k (Wilson-Hilferty:
// 0.10 for k = 1, 0.40 for k = 3, 0.54 for k = 5). The lower quartile, not the median: wrong
// matches within wide gates have large residuals, and a noisy rig's first frames, whose gates
// are still too tight, cut the large ones off; neither reaches the lower quarter much.
double ChiSquareQuartileRatio(int k) {
  const double v = 2.0 / (9.0 * k);
  const double t = 1.0 - v - 0.6745 * std::sqrt(v);
  return t * t * t;
}

}  // namespace

double RigMmPerPx(const Rig& rig) {
  if (rig.cameras.empty()) return 1.0;
  // The point nearest every optical axis: sum over cameras of (I - d d^T) (x - c) = 0.
  Eigen::Matrix3d normal = Eigen::Matrix3d::Zero();
  Eigen::Vector3d right = Eigen::Vector3d::Zero();
  Eigen::Vector3d mean_centre = Eigen::Vector3d::Zero();
  for (const Camera& camera : rig.cameras) {
    const Eigen::Vector3d centre = camera.CenterInWorld();
    const Eigen::Vector3d axis = camera.rotation.row(2).transpose();  // optical axis in the world
    const Eigen::Matrix3d across = Eigen::Matrix3d::Identity() - axis * axis.transpose();
    normal += across;
    right += across * centre;
    mean_centre += centre;
  }
  mean_centre /= static_cast<double>(rig.cameras.size());
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(normal);
  Eigen::Vector3d volume;
  if (eigen.eigenvalues().minCoeff() > 1e-3 * eigen.eigenvalues().maxCoeff()) {
    volume = normal.ldlt().solve(right);
  } else {
    // Parallel axes (a stereo pair looking one way): 3 m in front of the cameras.
    Eigen::Vector3d mean_axis = Eigen::Vector3d::Zero();
    for (const Camera& camera : rig.cameras) mean_axis += camera.rotation.row(2).transpose();
    volume = mean_centre + 3000.0 * mean_axis.normalized();
  }
  std::vector<double> scales;
  for (const Camera& camera : rig.cameras) {
    const double focal = 0.5 * (camera.intrinsics.fx + camera.intrinsics.fy);
    const double depth = camera.PointInCamera(volume).z();
    if (focal > 0.0 && depth > 0.0) scales.push_back(depth / focal);
  }
  if (scales.empty()) return 1.0;
  std::nth_element(scales.begin(), scales.begin() + static_cast<std::ptrdiff_t>(scales.size() / 2), scales.end());
  return scales[scales.size() / 2];
}

double CalibratedNoisePx(const Rig& rig) {
  double sum_squares = 0.0;
  int known = 0;
  for (const Camera& camera : rig.cameras) {
    if (!(camera.centroid_rms_px > 0.0)) continue;
    sum_squares += camera.centroid_rms_px * camera.centroid_rms_px;
    ++known;
  }
  return known == 0 ? 0.0 : std::sqrt(sum_squares / known / 2.0);
}

ReconstructorOptions GatesForNoise(const ReconstructorOptions& configured, double sigma_px, double mm_per_px) {
  ReconstructorOptions gates = configured;
  if (!(sigma_px > 0.0)) return gates;
  TriangulationOptions& triangulation = gates.triangulation;
  triangulation.max_reprojection_px =
      std::max(configured.triangulation.max_reprojection_px, NoiseGateFactors::kReprojectionSigmas * sigma_px);
  triangulation.max_merged_px = std::max(configured.triangulation.max_merged_px, triangulation.max_reprojection_px);
  const double ray_mm = NoiseGateFactors::kRaySigmas * sigma_px * mm_per_px;
  gates.graph.max_ray_distance_mm = std::max(configured.graph.max_ray_distance_mm, ray_mm);
  gates.clustering.max_ray_distance_mm = std::max(configured.clustering.max_ray_distance_mm, ray_mm);
  gates.prediction.min_gate_px =
      std::max(configured.prediction.min_gate_px, NoiseGateFactors::kPredictionGateSigmas * sigma_px);
  gates.prediction.max_gate_px = std::max(configured.prediction.max_gate_px, gates.prediction.min_gate_px);
  return gates;
}

CentroidNoiseMeter::CentroidNoiseMeter(double prior_px) : variance_(prior_px * prior_px) {}

void CentroidNoiseMeter::AddFrame(const std::vector<TriangulatedPoint>& points) {
  scratch_.clear();
  for (const TriangulatedPoint& point : points) {
    const int views = static_cast<int>(point.observations.size());
    if (views < 2) continue;
    const int dof = 2 * views - 3;
    const double sum_squares = views * point.rms_px * point.rms_px;
    scratch_.push_back(sum_squares / dof / ChiSquareQuartileRatio(dof));
  }
  if (static_cast<int>(scratch_.size()) < kMinPoints) return;
  const auto middle = scratch_.begin() + static_cast<std::ptrdiff_t>(scratch_.size() / 4);
  std::nth_element(scratch_.begin(), middle, scratch_.end());
  ++frames_;
  const double weight = 1.0 / static_cast<double>(std::min<long long>(frames_, kSettleFrames));
  variance_ += weight * (*middle - variance_);
}

double CentroidNoiseMeter::sigma_px() const { return std::sqrt(variance_); }

}  // namespace mocap

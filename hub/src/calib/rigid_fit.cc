// Kabsch / Umeyama: centre both sets, SVD of the cross-covariance, reflection guard on the
// smallest singular direction, scale from the ratio of spreads when requested.
#include "calib/rigid_fit.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include <Eigen/Dense>

namespace mocap {
namespace {

SimilarityTransform Fit(const std::vector<Eigen::Vector3d>& source,
                        const std::vector<Eigen::Vector3d>& target, bool with_scale) {
  if (source.size() != target.size()) {
    throw std::invalid_argument("point sets differ in size (" + std::to_string(source.size()) +
                                " vs " + std::to_string(target.size()) + ")");
  }
  if (source.size() < 3) throw std::invalid_argument("need at least 3 corresponding points");
  const double n = static_cast<double>(source.size());
  Eigen::Vector3d source_mean = Eigen::Vector3d::Zero();
  Eigen::Vector3d target_mean = Eigen::Vector3d::Zero();
  for (size_t i = 0; i < source.size(); ++i) {
    source_mean += source[i];
    target_mean += target[i];
  }
  source_mean /= n;
  target_mean /= n;
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  double source_spread = 0.0;
  for (size_t i = 0; i < source.size(); ++i) {
    const Eigen::Vector3d s = source[i] - source_mean;
    covariance += (target[i] - target_mean) * s.transpose();
    source_spread += s.squaredNorm();
  }
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(covariance, Eigen::ComputeFullU | Eigen::ComputeFullV);
  const Eigen::Vector3d singular = svd.singularValues();
  // Two vanishing singular values mean the points lie on a line: rotation about it is free.
  if (!(singular(1) > 1e-9 * std::max(singular(0), 1e-300))) {
    throw std::invalid_argument("points are collinear or coincident: rotation is undetermined");
  }
  Eigen::Matrix3d flip = Eigen::Matrix3d::Identity();
  if ((svd.matrixU() * svd.matrixV().transpose()).determinant() < 0.0) flip(2, 2) = -1.0;
  SimilarityTransform transform;
  transform.rotation = svd.matrixU() * flip * svd.matrixV().transpose();
  if (with_scale) {
    transform.scale = (singular.asDiagonal() * flip).trace() / source_spread;
  }
  transform.translation = target_mean - transform.scale * transform.rotation * source_mean;
  return transform;
}

}  // namespace

SimilarityTransform FitRigid(const std::vector<Eigen::Vector3d>& source,
                             const std::vector<Eigen::Vector3d>& target) {
  return Fit(source, target, false);
}

SimilarityTransform FitSimilarity(const std::vector<Eigen::Vector3d>& source,
                                  const std::vector<Eigen::Vector3d>& target) {
  return Fit(source, target, true);
}

double AlignmentRms(const SimilarityTransform& transform, const std::vector<Eigen::Vector3d>& source,
                    const std::vector<Eigen::Vector3d>& target) {
  if (source.empty() || source.size() != target.size()) {
    throw std::invalid_argument("AlignmentRms needs equal, non-empty point sets");
  }
  double sum = 0.0;
  for (size_t i = 0; i < source.size(); ++i) {
    sum += (transform.Apply(source[i]) - target[i]).squaredNorm();
  }
  return std::sqrt(sum / static_cast<double>(source.size()));
}

}  // namespace mocap

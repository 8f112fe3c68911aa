// Kabsch / Umeyama through Eigen::umeyama (reflection guard and scale included), behind a check
// that the correspondences determine a rotation at all, which umeyama does not make.
#include "geometry/rigid_fit.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include <Eigen/Dense>
#include <Eigen/Geometry>

namespace mocap {
namespace {

SimilarityTransform Fit(const std::vector<Eigen::Vector3d>& source,
                        const std::vector<Eigen::Vector3d>& target, bool with_scale) {
  if (source.size() != target.size()) {
    throw std::invalid_argument("point sets differ in size (" + std::to_string(source.size()) +
                                " vs " + std::to_string(target.size()) + ")");
  }
  if (source.size() < 3) throw std::invalid_argument("need at least 3 corresponding points");
  const Eigen::Index n = static_cast<Eigen::Index>(source.size());
  Eigen::Matrix3Xd source_points(3, n), target_points(3, n);
  for (Eigen::Index i = 0; i < n; ++i) {
    source_points.col(i) = source[i];
    target_points.col(i) = target[i];
  }
  // Two vanishing singular values of the cross-covariance mean the points lie on a line (or
  // coincide): rotation about that line is free and umeyama would return an arbitrary one.
  const Eigen::Matrix3Xd source_centred = source_points.colwise() - source_points.rowwise().mean();
  const Eigen::Matrix3Xd target_centred = target_points.colwise() - target_points.rowwise().mean();
  const Eigen::Vector3d singular =
      Eigen::JacobiSVD<Eigen::Matrix3d>(target_centred * source_centred.transpose()).singularValues();
  if (!(singular(1) > 1e-9 * std::max(singular(0), 1e-300))) {
    throw std::invalid_argument("points are collinear or coincident: rotation is undetermined");
  }
  const Eigen::Matrix4d target_from_source = Eigen::umeyama(source_points, target_points, with_scale);
  SimilarityTransform transform;
  const Eigen::Matrix3d scaled_rotation = target_from_source.topLeftCorner<3, 3>();
  if (with_scale) transform.scale = scaled_rotation.col(0).norm();
  transform.rotation = scaled_rotation / transform.scale;
  transform.translation = target_from_source.topRightCorner<3, 1>();
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

// Least-squares rigid and similarity transforms between corresponding 3D point sets (Kabsch,
// with Umeyama's scale). Used to place the world frame on an L-frame, to compare a calibration
// with ground truth whose world frame differs by a rigid motion, and to fit rigid bodies.
#pragma once

#include <vector>

#include <Eigen/Core>

namespace mocap {

// target_from_source: point_in_target = scale * rotation * point_in_source + translation.
struct SimilarityTransform {
  double scale = 1.0;
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();

  Eigen::Vector3d Apply(const Eigen::Vector3d& point) const {
    return scale * (rotation * point) + translation;
  }
};

// Throws std::invalid_argument when the sets differ in size, hold fewer than 3 points, or are
// degenerate (collinear), since no unique rotation exists then.
SimilarityTransform FitRigid(const std::vector<Eigen::Vector3d>& source,
                             const std::vector<Eigen::Vector3d>& target);
SimilarityTransform FitSimilarity(const std::vector<Eigen::Vector3d>& source,
                                  const std::vector<Eigen::Vector3d>& target);

// Root mean square distance between transform(source) and target.
double AlignmentRms(const SimilarityTransform& transform, const std::vector<Eigen::Vector3d>& source,
                    const std::vector<Eigen::Vector3d>& target);

}  // namespace mocap

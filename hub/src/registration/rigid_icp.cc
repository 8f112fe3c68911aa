// Rigid ICP with a k-d tree and Kabsch (see rigid_icp.h).
#include "registration/rigid_icp.h"

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <nanoflann.hpp>

namespace mocap {

struct NearestPoints::Index {
  struct Cloud {
    const std::vector<Eigen::Vector3d>* points;
    size_t kdtree_get_point_count() const { return points->size(); }
    double kdtree_get_pt(size_t i, size_t dim) const { return (*points)[i][static_cast<Eigen::Index>(dim)]; }
    template <class Box>
    bool kdtree_get_bbox(Box&) const {
      return false;
    }
  };
  using Tree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, Cloud>, Cloud, 3, size_t>;

  explicit Index(const std::vector<Eigen::Vector3d>& points) : cloud{&points}, tree(3, cloud) {}
  Cloud cloud;
  Tree tree;
};

NearestPoints::NearestPoints(const std::vector<Eigen::Vector3d>& points) : index_(new Index(points)) {}

NearestPoints::~NearestPoints() { delete index_; }

size_t NearestPoints::Nearest(const Eigen::Vector3d& query, double* squared_distance) const {
  size_t index = 0;
  double distance = 0.0;
  index_->tree.knnSearch(query.data(), 1, &index, &distance);
  if (squared_distance != nullptr) *squared_distance = distance;
  return index;
}

namespace {

Eigen::Vector3d Centroid(const std::vector<Eigen::Vector3d>& points) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& p : points) sum += p;
  return sum / static_cast<double>(points.size());
}

// Principal axes as columns, largest spread first, forming a right-handed frame.
Eigen::Matrix3d PrincipalAxes(const std::vector<Eigen::Vector3d>& points, const Eigen::Vector3d& centroid) {
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  for (const Eigen::Vector3d& p : points) covariance += (p - centroid) * (p - centroid).transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(covariance);
  Eigen::Matrix3d axes;
  for (int i = 0; i < 3; ++i) axes.col(i) = solver.eigenvectors().col(2 - i);
  if (axes.determinant() < 0) axes.col(2) = -axes.col(2);
  return axes;
}

RigidIcpResult RunIcp(const std::vector<Eigen::Vector3d>& source, const std::vector<Eigen::Vector3d>& target,
                      const NearestPoints& nearest, SimilarityTransform transform, const RigidIcpOptions& options) {
  RigidIcpResult result;
  const double max_squared = options.max_pair_distance_mm > 0.0
                                 ? options.max_pair_distance_mm * options.max_pair_distance_mm
                                 : std::numeric_limits<double>::infinity();
  double previous = std::numeric_limits<double>::infinity();
  std::vector<Eigen::Vector3d> from, to;
  for (int iteration = 1; iteration <= options.max_iterations; ++iteration) {
    from.clear();
    to.clear();
    double sum = 0.0;
    for (const Eigen::Vector3d& p : source) {
      double squared = 0.0;
      const size_t j = nearest.Nearest(transform.Apply(p), &squared);
      if (squared > max_squared) continue;
      from.push_back(p);
      to.push_back(target[j]);
      sum += squared;
    }
    result.iterations = iteration;
    if (from.size() < 3) {
      result.rms_mm = std::numeric_limits<double>::infinity();
      result.pairs = from.size();
      return result;
    }
    const double rms = std::sqrt(sum / static_cast<double>(from.size()));
    result.target_from_source = transform;
    result.rms_mm = rms;
    result.pairs = from.size();
    if (previous - rms < options.tolerance_mm) break;
    previous = rms;
    try {
      transform = FitRigid(from, to);
    } catch (const std::invalid_argument&) {
      break;  // the pairs are collinear: no unique rotation, keep the last one
    }
  }
  return result;
}

// Gauss-Newton on (R p + t - q) . n over the nearest pairs, a small rotation w and shift d per
// step: (R p + t) + w x (R p + t) + d.
RigidIcpResult RefinePointToPlane(const std::vector<Eigen::Vector3d>& source, const std::vector<Eigen::Vector3d>& target,
                                  const std::vector<Eigen::Vector3d>& normals, const NearestPoints& nearest,
                                  RigidIcpResult result, const RigidIcpOptions& options) {
  const double max_squared = options.max_pair_distance_mm > 0.0
                                 ? options.max_pair_distance_mm * options.max_pair_distance_mm
                                 : std::numeric_limits<double>::infinity();
  SimilarityTransform transform = result.target_from_source;
  for (int iteration = 0; iteration < options.max_iterations; ++iteration) {
    Eigen::Matrix<double, 6, 6> normal_matrix = Eigen::Matrix<double, 6, 6>::Zero();
    Eigen::Matrix<double, 6, 1> rhs = Eigen::Matrix<double, 6, 1>::Zero();
    double sum = 0.0;
    size_t pairs = 0;
    for (const Eigen::Vector3d& p : source) {
      const Eigen::Vector3d moved = transform.Apply(p);
      double squared = 0.0;
      const size_t j = nearest.Nearest(moved, &squared);
      if (squared > max_squared) continue;
      Eigen::Matrix<double, 6, 1> row;
      row << moved.cross(normals[j]), normals[j];
      const double residual = (moved - target[j]).dot(normals[j]);
      normal_matrix += row * row.transpose();
      rhs -= row * residual;
      sum += residual * residual;
      ++pairs;
    }
    if (pairs < 6) break;
    result.target_from_source = transform;
    result.rms_mm = std::sqrt(sum / static_cast<double>(pairs));
    result.pairs = pairs;
    // A little damping keeps a direction the surface leaves free (a sphere's turns) from jumping.
    normal_matrix.diagonal().array() += 1e-9 * normal_matrix.trace();
    const Eigen::Matrix<double, 6, 1> step = normal_matrix.ldlt().solve(rhs);
    if (!step.allFinite()) break;
    const Eigen::Vector3d w = step.head<3>();
    const Eigen::Matrix3d turn =
        w.norm() > 0.0 ? Eigen::AngleAxisd(w.norm(), w.normalized()).toRotationMatrix() : Eigen::Matrix3d::Identity();
    transform.rotation = turn * transform.rotation;
    transform.translation = turn * transform.translation + step.tail<3>();
    if (w.norm() < 1e-10 && step.tail<3>().norm() < 1e-7) {
      result.target_from_source = transform;
      break;
    }
  }
  return result;
}

}  // namespace

void RigidIcpOptions::Check() const {
  if (max_iterations < 1 || max_iterations > 10000)
    throw std::invalid_argument("max_iterations: " + std::to_string(max_iterations) + " is outside 1..10000");
  if (!(tolerance_mm >= 0.0 && std::isfinite(tolerance_mm)))
    throw std::invalid_argument("tolerance_mm: " + std::to_string(tolerance_mm) + " must be a finite number >= 0");
  if (!(max_pair_distance_mm >= 0.0 && std::isfinite(max_pair_distance_mm)))
    throw std::invalid_argument("max_pair_distance_mm: " + std::to_string(max_pair_distance_mm) +
                                " must be a finite number >= 0 (0: keep every pair)");
}

RigidIcpResult AlignRigidIcp(const std::vector<Eigen::Vector3d>& source, const std::vector<Eigen::Vector3d>& target,
                             const RigidIcpOptions& options, const std::vector<Eigen::Vector3d>* target_normals) {
  options.Check();
  if (target_normals != nullptr && target_normals->size() != target.size())
    throw std::invalid_argument("rigid ICP: " + std::to_string(target_normals->size()) + " normals for " +
                                std::to_string(target.size()) + " target points");
  if (source.size() < 3 || target.size() < 3)
    throw std::invalid_argument("rigid ICP needs at least 3 points in each set (source " + std::to_string(source.size()) +
                                ", target " + std::to_string(target.size()) + ")");
  const NearestPoints nearest(target);
  const Eigen::Vector3d source_centroid = Centroid(source), target_centroid = Centroid(target);
  std::vector<Eigen::Matrix3d> rotations = {Eigen::Matrix3d::Identity()};
  if (options.principal_axis_starts) {
    const Eigen::Matrix3d source_axes = PrincipalAxes(source, source_centroid);
    const Eigen::Matrix3d target_axes = PrincipalAxes(target, target_centroid);
    for (const Eigen::Vector3d& signs : {Eigen::Vector3d(1, 1, 1), Eigen::Vector3d(-1, -1, 1), Eigen::Vector3d(-1, 1, -1),
                                         Eigen::Vector3d(1, -1, -1)})
      rotations.push_back(target_axes * signs.asDiagonal() * source_axes.transpose());
  }
  RigidIcpResult best;
  best.rms_mm = std::numeric_limits<double>::infinity();
  for (const Eigen::Matrix3d& rotation : rotations) {
    SimilarityTransform start;
    start.rotation = rotation;
    start.translation = target_centroid - rotation * source_centroid;
    const RigidIcpResult result = RunIcp(source, target, nearest, start, options);
    if (result.pairs > best.pairs || (result.pairs == best.pairs && result.rms_mm < best.rms_mm)) best = result;
  }
  if (target_normals != nullptr && std::isfinite(best.rms_mm))
    best = RefinePointToPlane(source, target, *target_normals, nearest, best, options);
  return best;
}

}  // namespace mocap

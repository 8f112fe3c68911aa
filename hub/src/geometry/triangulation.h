// Multi-view triangulation of one point from undistorted normalized image coordinates: the one
// core behind calibration (wand start, wand lengths, L-frame) and recon's robust per-marker
// triangulation. Views are fed one at a time into small accumulators so that the per-frame hot
// path builds no view lists: it hands over its camera poses and observations in place.
#pragma once

#include <vector>

#include <Eigen/Core>

namespace mocap {

// Linear estimate: each view contributes (x r3 - r1) X = t1 - x t3 and the same for y, with the
// point's homogeneous coordinate fixed to 1, accumulated straight into 3x3 normal equations.
class LinearTriangulation {
 public:
  void AddView(const Eigen::Matrix3d& cam_from_world_rotation,
               const Eigen::Vector3d& cam_from_world_translation, const Eigen::Vector2d& normalized);
  // False when fewer than two views were added or the rays are (nearly) parallel, so that the
  // point is not determined; *point_in_world is left untouched then.
  bool Solve(Eigen::Vector3d* point_in_world) const;

 private:
  Eigen::Matrix3d normal_ = Eigen::Matrix3d::Zero();
  Eigen::Vector3d rhs_ = Eigen::Vector3d::Zero();
  int views_ = 0;
};

// One Gauss-Newton step on the reprojection error of a point, each view's residual scaled by
// its weight (1 for normalized units, the focal length for pixels).
class GaussNewtonTriangulationStep {
 public:
  explicit GaussNewtonTriangulationStep(const Eigen::Vector3d& point_in_world) : point_(point_in_world) {}
  // False when the point is not strictly in front of this camera; the step is undefined then.
  bool AddView(const Eigen::Matrix3d& cam_from_world_rotation,
               const Eigen::Vector3d& cam_from_world_translation, const Eigen::Vector2d& normalized,
               double weight);
  // The step to subtract from the point; false when the normal equations break down.
  bool Solve(Eigen::Vector3d* step) const;

 private:
  Eigen::Vector3d point_;
  Eigen::Matrix3d normal_ = Eigen::Matrix3d::Zero();
  Eigen::Vector3d gradient_ = Eigen::Vector3d::Zero();
};

// One view of a point for the list-based driver below: the camera's normalized projection
// matrix [R|t] and the undistorted normalized coordinates observed there.
struct PointView {
  Eigen::Matrix<double, 3, 4> cam_from_world;
  Eigen::Vector2d normalized;
};

// Linear estimate refined by up to five Gauss-Newton steps on the normalized reprojection
// error (kept as it is when a step would put it behind a camera). False as for
// LinearTriangulation::Solve.
bool TriangulatePoint(const std::vector<PointView>& views, Eigen::Vector3d* point_in_world);

// AddView runs once per view per iteration in recon's per-frame loop: defined here so that it
// inlines into the callers' loops like the hand-written accumulation it replaced.
inline void LinearTriangulation::AddView(const Eigen::Matrix3d& cam_from_world_rotation,
                                  const Eigen::Vector3d& cam_from_world_translation,
                                  const Eigen::Vector2d& normalized) {
  for (int axis = 0; axis < 2; ++axis) {
    const double coord = normalized[axis];
    const Eigen::RowVector3d row = coord * cam_from_world_rotation.row(2) - cam_from_world_rotation.row(axis);
    const double b = cam_from_world_translation[axis] - coord * cam_from_world_translation[2];
    normal_.noalias() += row.transpose() * row;
    rhs_.noalias() += row.transpose() * b;
  }
  ++views_;
}

inline bool GaussNewtonTriangulationStep::AddView(const Eigen::Matrix3d& cam_from_world_rotation,
                                           const Eigen::Vector3d& cam_from_world_translation,
                                           const Eigen::Vector2d& normalized, double weight) {
  const Eigen::Vector3d p = cam_from_world_rotation * point_ + cam_from_world_translation;
  if (!(p.z() > 1e-9)) return false;
  const double inv_z = 1.0 / p.z();
  const Eigen::Vector2d projected(p.x() * inv_z, p.y() * inv_z);
  const Eigen::Vector2d residual = weight * (projected - normalized);
  Eigen::Matrix<double, 2, 3> d_proj_d_cam;
  d_proj_d_cam << inv_z, 0.0, -projected.x() * inv_z, 0.0, inv_z, -projected.y() * inv_z;
  const Eigen::Matrix<double, 2, 3> jacobian = weight * d_proj_d_cam * cam_from_world_rotation;
  normal_.noalias() += jacobian.transpose() * jacobian;
  gradient_.noalias() += jacobian.transpose() * residual;
  return true;
}

}  // namespace mocap

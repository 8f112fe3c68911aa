// Normal-equation triangulation. Hand-written 3-parameter solves rather than Ceres: recon runs
// them for every marker of every frame, and the 3x3 systems cost well under a microsecond where
// a Ceres problem's set-up alone costs tens.
#include "geometry/triangulation.h"

#include <Eigen/Dense>

namespace mocap {

bool LinearTriangulation::Solve(Eigen::Vector3d* point_in_world) const {
  if (views_ < 2) return false;
  const Eigen::LDLT<Eigen::Matrix3d> solver(normal_);
  // Parallel rays leave the normal matrix (nearly) singular: compare its pivots. Cheaper than
  // rcond(), which estimates a norm of the inverse.
  const Eigen::Vector3d pivots = solver.vectorD().cwiseAbs();
  if (solver.info() != Eigen::Success || !(pivots.minCoeff() > 1e-12 * pivots.maxCoeff())) return false;
  const Eigen::Vector3d point = solver.solve(rhs_);
  if (!point.allFinite()) return false;
  *point_in_world = point;
  return true;
}

bool GaussNewtonTriangulationStep::Solve(Eigen::Vector3d* step) const {
  const Eigen::LDLT<Eigen::Matrix3d> solver(normal_);
  if (solver.info() != Eigen::Success) return false;
  *step = solver.solve(gradient_);
  return step->allFinite();
}

bool TriangulatePoint(const std::vector<PointView>& views, Eigen::Vector3d* point_in_world) {
  LinearTriangulation linear;
  for (const PointView& view : views) {
    linear.AddView(view.cam_from_world.leftCols<3>(), view.cam_from_world.col(3), view.normalized);
  }
  Eigen::Vector3d point;
  if (!linear.Solve(&point)) return false;
  for (int iteration = 0; iteration < 5; ++iteration) {
    GaussNewtonTriangulationStep gauss_newton(point);
    bool in_front = true;
    for (const PointView& view : views) {
      in_front = in_front && gauss_newton.AddView(view.cam_from_world.leftCols<3>(), view.cam_from_world.col(3),
                                                  view.normalized, 1.0);
    }
    Eigen::Vector3d step;
    if (!in_front || !gauss_newton.Solve(&step)) break;
    point -= step;
    if (step.norm() < 1e-9 * (1.0 + point.norm())) break;
  }
  *point_in_world = point;
  return true;
}

}  // namespace mocap

// Homogeneous DLT triangulation in a conditioned frame (origin at the mean camera centre, unit
// scale at the mean camera distance) so that algebraic and geometric error agree, then a few
// Gauss-Newton steps on the normalized reprojection error.
#include "calib/triangulation.h"

#include <cmath>
#include <limits>

#include <Eigen/Dense>

namespace mocap {
namespace {

void RefineGaussNewton(const std::vector<PointView>& views, Eigen::Vector3d* point) {
  for (int iteration = 0; iteration < 5; ++iteration) {
    Eigen::Matrix3d normal = Eigen::Matrix3d::Zero();
    Eigen::Vector3d gradient = Eigen::Vector3d::Zero();
    for (const PointView& view : views) {
      const Eigen::Vector3d in_cam = view.cam_from_world.leftCols<3>() * *point + view.cam_from_world.col(3);
      if (!(in_cam.z() > 1e-9)) return;
      const double inv_z = 1.0 / in_cam.z();
      const Eigen::Vector2d residual = in_cam.head<2>() * inv_z - view.normalized;
      Eigen::Matrix<double, 2, 3> d_projection;
      d_projection << inv_z, 0.0, -in_cam.x() * inv_z * inv_z, 0.0, inv_z, -in_cam.y() * inv_z * inv_z;
      const Eigen::Matrix<double, 2, 3> jacobian = d_projection * view.cam_from_world.leftCols<3>();
      normal += jacobian.transpose() * jacobian;
      gradient += jacobian.transpose() * residual;
    }
    const Eigen::Vector3d step = normal.ldlt().solve(gradient);
    if (!step.allFinite()) return;
    *point -= step;
    if (step.norm() < 1e-9 * (1.0 + point->norm())) return;
  }
}

}  // namespace

bool TriangulateLinear(const std::vector<PointView>& views, Eigen::Vector3d* point_in_world) {
  if (views.size() < 2) return false;
  // Conditioning: world = origin + scale * conditioned.
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  std::vector<Eigen::Vector3d> centres;
  for (const PointView& view : views) {
    centres.push_back(-view.cam_from_world.leftCols<3>().transpose() * view.cam_from_world.col(3));
    origin += centres.back();
  }
  origin /= static_cast<double>(views.size());
  double scale = 0.0;
  for (const Eigen::Vector3d& c : centres) scale += (c - origin).norm();
  scale = scale > 0.0 ? scale / static_cast<double>(views.size()) : 1.0;
  Eigen::Matrix4d world_from_conditioned = Eigen::Matrix4d::Identity();
  world_from_conditioned.topLeftCorner<3, 3>() *= scale;
  world_from_conditioned.topRightCorner<3, 1>() = origin;

  Eigen::MatrixXd design(2 * views.size(), 4);
  for (size_t i = 0; i < views.size(); ++i) {
    const Eigen::Matrix<double, 3, 4> p = views[i].cam_from_world * world_from_conditioned;
    const Eigen::Vector2d& x = views[i].normalized;
    const Eigen::RowVector4d row_u = x.x() * p.row(2) - p.row(0);
    const Eigen::RowVector4d row_v = x.y() * p.row(2) - p.row(1);
    design.row(2 * i) = row_u / row_u.norm();
    design.row(2 * i + 1) = row_v / row_v.norm();
  }
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(design, Eigen::ComputeFullV);
  const Eigen::VectorXd singular = svd.singularValues();
  // Parallel rays leave a two-dimensional null space: the point is anywhere along them.
  if (!(singular(2) > 1e-9)) return false;
  const Eigen::Vector4d homogeneous = world_from_conditioned * svd.matrixV().col(3);
  if (std::abs(homogeneous(3)) < 1e-14) return false;
  Eigen::Vector3d point = homogeneous.head<3>() / homogeneous(3);
  if (!point.allFinite()) return false;
  RefineGaussNewton(views, &point);
  if (!point.allFinite()) return false;
  *point_in_world = point;
  return true;
}

double ReprojectionRmsPx(const std::vector<const Camera*>& cameras,
                         const std::vector<Eigen::Vector2d>& pixels, const Eigen::Vector3d& point_in_world) {
  if (cameras.empty()) return 0.0;
  double sum = 0.0;
  for (size_t i = 0; i < cameras.size(); ++i) {
    Eigen::Vector2d projected;
    if (!cameras[i]->ProjectToPixel(point_in_world, &projected)) {
      return std::numeric_limits<double>::infinity();
    }
    sum += (projected - pixels[i]).squaredNorm();
  }
  return std::sqrt(sum / static_cast<double>(cameras.size()));
}

}  // namespace mocap

// Linear + Gauss-Newton triangulation. A hand-written 3-parameter solve rather than Ceres: it
// runs for every marker of every frame, and the 3x3 normal equations cost well under a
// microsecond where a Ceres problem's set-up alone costs tens.
#include "recon/triangulation.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Dense>

namespace mocap {

bool TriangulateLinear(const RigModel& rig, const FrameViews& views,
                       const std::vector<int>& observations, Eigen::Vector3d* point_in_world) {
  if (observations.size() < 2) return false;
  // Each view gives rows (x * r3 - r1) X = t1 - x * t3 and the same for y; accumulate the
  // normal equations directly instead of building the 2n x 3 matrix.
  Eigen::Matrix3d normal = Eigen::Matrix3d::Zero();
  Eigen::Vector3d rhs = Eigen::Vector3d::Zero();
  for (int index : observations) {
    const Observation& obs = views.observations[index];
    const CameraModel& cam = rig.camera(obs.camera);
    const Eigen::Matrix3d& r = cam.cam_from_world_rotation;
    const Eigen::Vector3d& t = cam.cam_from_world_translation;
    for (int axis = 0; axis < 2; ++axis) {
      const double coord = obs.normalized[axis];
      const Eigen::RowVector3d row = coord * r.row(2) - r.row(axis);
      const double b = t[axis] - coord * t[2];
      normal.noalias() += row.transpose() * row;
      rhs.noalias() += row.transpose() * b;
    }
  }
  const Eigen::LDLT<Eigen::Matrix3d> solver(normal);
  // Parallel rays leave the normal matrix (nearly) singular: compare its pivots. Cheaper than
  // rcond(), which estimates a norm of the inverse.
  const Eigen::Vector3d pivots = solver.vectorD().cwiseAbs();
  if (solver.info() != Eigen::Success || !(pivots.minCoeff() > 1e-12 * pivots.maxCoeff())) return false;
  *point_in_world = solver.solve(rhs);
  return point_in_world->allFinite();
}

bool RefinePoint(const RigModel& rig, const FrameViews& views, const std::vector<int>& observations,
                 int iterations, Eigen::Vector3d* point_in_world) {
  Eigen::Vector3d point = *point_in_world;
  for (int iteration = 0; iteration < iterations; ++iteration) {
    Eigen::Matrix3d normal = Eigen::Matrix3d::Zero();
    Eigen::Vector3d gradient = Eigen::Vector3d::Zero();
    for (int index : observations) {
      const Observation& obs = views.observations[index];
      const CameraModel& cam = rig.camera(obs.camera);
      const Eigen::Vector3d p = cam.cam_from_world_rotation * point + cam.cam_from_world_translation;
      if (!(p.z() > 1e-9)) return false;
      const double inv_z = 1.0 / p.z();
      const Eigen::Vector2d projected(p.x() * inv_z, p.y() * inv_z);
      const Eigen::Vector2d residual = cam.focal_px * (projected - obs.normalized);
      Eigen::Matrix<double, 2, 3> d_proj_d_cam;
      d_proj_d_cam << inv_z, 0.0, -projected.x() * inv_z, 0.0, inv_z, -projected.y() * inv_z;
      const Eigen::Matrix<double, 2, 3> jacobian =
          cam.focal_px * d_proj_d_cam * cam.cam_from_world_rotation;
      normal.noalias() += jacobian.transpose() * jacobian;
      gradient.noalias() += jacobian.transpose() * residual;
    }
    const Eigen::LDLT<Eigen::Matrix3d> solver(normal);
    if (solver.info() != Eigen::Success) return false;
    const Eigen::Vector3d step = solver.solve(gradient);
    if (!step.allFinite()) return false;
    point -= step;
    // Steps under a micrometre change nothing measurable; stop early to save time.
    if (step.squaredNorm() < 1e-6) break;
  }
  *point_in_world = point;
  return true;
}

void ReprojectionErrors(const RigModel& rig, const FrameViews& views,
                        const std::vector<int>& observations, const Eigen::Vector3d& point_in_world,
                        std::vector<double>* errors_px) {
  errors_px->resize(observations.size());
  for (size_t i = 0; i < observations.size(); ++i) {
    const Observation& obs = views.observations[observations[i]];
    const CameraModel& cam = rig.camera(obs.camera);
    const Eigen::Vector3d p =
        cam.cam_from_world_rotation * point_in_world + cam.cam_from_world_translation;
    if (!(p.z() > 1e-9)) {
      (*errors_px)[i] = HUGE_VAL;
      continue;
    }
    (*errors_px)[i] = cam.focal_px * (p.head<2>() / p.z() - obs.normalized).norm();
  }
}

namespace {

bool InFrontOfAll(const RigModel& rig, const FrameViews& views, const std::vector<int>& observations,
                  const Eigen::Vector3d& point, double min_depth_mm) {
  for (int index : observations) {
    const CameraModel& cam = rig.camera(views.observations[index].camera);
    const double depth =
        cam.cam_from_world_rotation.row(2).dot(point) + cam.cam_from_world_translation.z();
    if (depth < min_depth_mm) return false;
  }
  return true;
}

}  // namespace

bool TriangulateRobust(const RigModel& rig, const FrameViews& views, std::vector<int> observations,
                       const TriangulationOptions& options, TriangulatedPoint* result) {
  result->rejected.clear();
  std::vector<double> errors;
  while (static_cast<int>(observations.size()) >= options.min_views) {
    Eigen::Vector3d point;
    if (!TriangulateLinear(rig, views, observations, &point)) return false;
    if (!RefinePoint(rig, views, observations, options.refine_iterations, &point)) return false;
    ReprojectionErrors(rig, views, observations, point, &errors);
    const auto worst = std::max_element(errors.begin(), errors.end());
    const bool in_front = InFrontOfAll(rig, views, observations, point, options.min_depth_mm);
    if (*worst <= options.max_reprojection_px && in_front) {
      double sum_squares = 0.0;
      for (double e : errors) sum_squares += e * e;
      result->point_in_world = point;
      result->rms_px = std::sqrt(sum_squares / errors.size());
      result->max_px = *worst;
      result->observations = std::move(observations);
      return true;
    }
    // With two views a large residual cannot say which view is wrong: give up.
    if (observations.size() <= 2) return false;
    const size_t drop = static_cast<size_t>(worst - errors.begin());
    result->rejected.push_back(observations[drop]);
    observations.erase(observations.begin() + static_cast<std::ptrdiff_t>(drop));
  }
  return false;
}

}  // namespace mocap

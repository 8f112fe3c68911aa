// The shared triangulation core: exact views give the point back, noisy views are pulled to
// the reprojection-error minimum by the Gauss-Newton steps, degenerate inputs are refused.
#include "geometry/triangulation.h"

#include <random>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

namespace mocap {
namespace {

// A camera at `centre` looking at the origin.
Eigen::Matrix<double, 3, 4> LookAtOrigin(const Eigen::Vector3d& centre) {
  const Eigen::Vector3d z = -centre.normalized();
  const Eigen::Vector3d x = Eigen::Vector3d::UnitZ().cross(z).normalized();
  const Eigen::Vector3d y = z.cross(x);
  Eigen::Matrix3d rotation;
  rotation << x.transpose(), y.transpose(), z.transpose();
  Eigen::Matrix<double, 3, 4> cam_from_world;
  cam_from_world << rotation, -rotation * centre;
  return cam_from_world;
}

Eigen::Vector2d Project(const Eigen::Matrix<double, 3, 4>& cam_from_world, const Eigen::Vector3d& point) {
  return (cam_from_world * point.homogeneous()).hnormalized();
}

std::vector<PointView> ViewsOf(const Eigen::Vector3d& point) {
  std::vector<PointView> views;
  for (const Eigen::Vector3d& centre : {Eigen::Vector3d(3000, 0, 1500), Eigen::Vector3d(0, 3000, 1800),
                                        Eigen::Vector3d(-2500, -1500, 1200)}) {
    const Eigen::Matrix<double, 3, 4> cam_from_world = LookAtOrigin(centre);
    views.push_back({cam_from_world, Project(cam_from_world, point)});
  }
  return views;
}

TEST(Triangulation, ExactViewsGiveThePointBack) {
  const Eigen::Vector3d truth(120.0, -340.0, 560.0);
  Eigen::Vector3d point;
  ASSERT_TRUE(TriangulatePoint(ViewsOf(truth), &point));
  EXPECT_LT((point - truth).norm(), 1e-6);
}

TEST(Triangulation, GaussNewtonReachesTheNoisyMinimum) {
  const Eigen::Vector3d truth(-80.0, 200.0, 900.0);
  std::vector<PointView> views = ViewsOf(truth);
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0.0, 5e-4);
  for (PointView& view : views) view.normalized += Eigen::Vector2d(noise(rng), noise(rng));
  Eigen::Vector3d point;
  ASSERT_TRUE(TriangulatePoint(views, &point));
  // At the minimum the gradient vanishes: one more step moves the point by (almost) nothing.
  GaussNewtonTriangulationStep gauss_newton(point);
  for (const PointView& view : views) {
    ASSERT_TRUE(gauss_newton.AddView(view.cam_from_world.leftCols<3>(), view.cam_from_world.col(3),
                                     view.normalized, 1.0));
  }
  Eigen::Vector3d step;
  ASSERT_TRUE(gauss_newton.Solve(&step));
  EXPECT_LT(step.norm(), 1e-6);
  EXPECT_LT((point - truth).norm(), 10.0);
}

TEST(Triangulation, DegenerateInputsAreRefused) {
  const Eigen::Vector3d truth(0.0, 0.0, 500.0);
  Eigen::Vector3d point(1.0, 2.0, 3.0);
  std::vector<PointView> one_view = ViewsOf(truth);
  one_view.resize(1);
  EXPECT_FALSE(TriangulatePoint(one_view, &point));
  // Two cameras on one line through the point see it along the same ray.
  std::vector<PointView> parallel;
  for (double distance : {2000.0, 4000.0}) {
    const Eigen::Matrix<double, 3, 4> cam_from_world = LookAtOrigin(Eigen::Vector3d(distance, 0.0, 500.0));
    parallel.push_back({cam_from_world, Project(cam_from_world, truth)});
  }
  EXPECT_FALSE(TriangulatePoint(parallel, &point));
  EXPECT_EQ(point, Eigen::Vector3d(1.0, 2.0, 3.0));
}

TEST(Triangulation, StepRefusesAPointBehindTheCamera) {
  const Eigen::Matrix<double, 3, 4> cam_from_world = LookAtOrigin(Eigen::Vector3d(3000, 0, 0));
  GaussNewtonTriangulationStep gauss_newton(Eigen::Vector3d(6000, 0, 0));
  EXPECT_FALSE(gauss_newton.AddView(cam_from_world.leftCols<3>(), cam_from_world.col(3), Eigen::Vector2d::Zero(), 1.0));
}

}  // namespace
}  // namespace mocap

// DLT in three stages: Hartley-normalised homogeneous solve (SVD), scaled so that the 12th
// element is 1 as in the seed's parametrisation; RQ decomposition into K [R | t] (OpenCV); Ceres
// refinement with the shared KnownPointReprojectionError.
#include "calib/dlt.h"

#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>

#include <ceres/manifold.h>
#include <ceres/problem.h>
#include <ceres/solver.h>
#include <Eigen/Dense>
#include <opencv2/calib3d.hpp>

#include "calib/camera_blocks.h"
#include "calib/cost_functions.h"
#include "util/bounded_line.h"

namespace mocap {
namespace {

double CameraRmsPx(const Camera& camera, const std::vector<ControlPoint>& points) {
  double sum = 0.0;
  for (const ControlPoint& p : points) {
    Eigen::Vector2d projected;
    if (!camera.ProjectToPixel(p.point_in_world, &projected)) return std::numeric_limits<double>::infinity();
    sum += (projected - p.pixel).squaredNorm();
  }
  return std::sqrt(sum / static_cast<double>(points.size()));
}

// Hartley-normalised homogeneous DLT: centroid to the origin, mean distance sqrt(3) (3D) and
// sqrt(2) (2D), SVD null vector, normalisations undone, scaled so that P(2,3) = 1 (the seed's
// parametrisation with L12 = 1).
Eigen::Matrix<double, 3, 4> SolveNormalizedDlt(const std::vector<ControlPoint>& points) {
  const size_t n = points.size();
  if (n < 6) throw std::invalid_argument("DLT needs at least 6 control points, got " + std::to_string(n));
  Eigen::Vector3d mean3 = Eigen::Vector3d::Zero();
  Eigen::Vector2d mean2 = Eigen::Vector2d::Zero();
  for (const ControlPoint& p : points) {
    mean3 += p.point_in_world;
    mean2 += p.pixel;
  }
  mean3 /= static_cast<double>(n);
  mean2 /= static_cast<double>(n);
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  double spread3 = 0.0, spread2 = 0.0;
  for (const ControlPoint& p : points) {
    const Eigen::Vector3d d = p.point_in_world - mean3;
    scatter += d * d.transpose();
    spread3 += d.norm();
    spread2 += (p.pixel - mean2).norm();
  }
  const Eigen::Vector3d extent = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(scatter).eigenvalues();
  if (!(extent(0) > 1e-6 * extent(2))) {
    throw std::invalid_argument("the control points are coplanar (or collinear): DLT needs points spread in depth");
  }
  const double s3 = std::sqrt(3.0) * static_cast<double>(n) / spread3;
  const double s2 = std::sqrt(2.0) * static_cast<double>(n) / spread2;
  Eigen::MatrixXd design(2 * n, 12);
  for (size_t i = 0; i < n; ++i) {
    const Eigen::Vector4d x((points[i].point_in_world - mean3).x() * s3, (points[i].point_in_world - mean3).y() * s3,
                            (points[i].point_in_world - mean3).z() * s3, 1.0);
    const Eigen::Vector2d u = (points[i].pixel - mean2) * s2;
    design.row(2 * i) << x.transpose(), Eigen::RowVector4d::Zero(), -u.x() * x.transpose();
    design.row(2 * i + 1) << Eigen::RowVector4d::Zero(), x.transpose(), -u.y() * x.transpose();
  }
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(design, Eigen::ComputeFullV);
  const Eigen::VectorXd h = svd.matrixV().col(11);
  Eigen::Matrix<double, 3, 4> normalized_p;
  normalized_p << h.segment<4>(0).transpose(), h.segment<4>(4).transpose(), h.segment<4>(8).transpose();
  // Undo the normalisations: P = T2^-1 * Pn * T3.
  Eigen::Matrix3d t2_inverse = Eigen::Matrix3d::Identity();
  t2_inverse.topLeftCorner<2, 2>() /= s2;
  t2_inverse.topRightCorner<2, 1>() = mean2;
  Eigen::Matrix4d t3 = Eigen::Matrix4d::Identity();
  t3.topLeftCorner<3, 3>() *= s3;
  t3.topRightCorner<3, 1>() = -s3 * mean3;
  Eigen::Matrix<double, 3, 4> p = t2_inverse * normalized_p * t3;
  if (!(std::abs(p(2, 3)) > 1e-12 * p.norm())) {
    throw std::invalid_argument("the world origin lies in the camera's focal plane: move the control points' origin");
  }
  p /= p(2, 3);
  return p;
}

// RQ decomposition of P's left 3x3 block into K R (OpenCV's Givens-rotation RQDecomp3x3), with
// K's diagonal made positive, and t = K^-1 p4. The skew of K, which the OpenCV camera model
// cannot hold, goes to *skew_px.
Camera DecomposeProjection(const Eigen::Matrix<double, 3, 4>& p, const DltOptions& options, double* skew_px) {
  // P is defined up to scale and sign. Scale: a unit third row (K(2,2) = 1), because
  // RQDecomp3x3 adds DBL_EPSILON under its Givens normalisations, which costs digits on a small
  // third row (L9-L11 ~ 1e-4 with L12 = 1). Sign: the camera needs det(R) = +1.
  const double norm = p.block<1, 3>(2, 0).norm();
  const double sign = p.leftCols<3>().determinant() < 0.0 ? -1.0 : 1.0;
  const Eigen::Matrix3d m = p.leftCols<3>() * (sign / norm);
  const Eigen::Vector3d p4 = p.col(3) * (sign / norm);
  cv::Matx33d m_cv, k_cv, r_cv;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) m_cv(i, j) = m(i, j);
  }
  cv::RQDecomp3x3(m_cv, k_cv, r_cv);
  Eigen::Matrix3d k, r;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      k(i, j) = k_cv(i, j);
      r(i, j) = r_cv(i, j);
    }
  }
  // det(R) = +1 and det(M) > 0 leave an even number of negative diagonal entries in K: flipping
  // them in pairs (column of K, row of R) keeps det(R) = +1.
  for (int i = 0; i < 3; ++i) {
    if (k(i, i) < 0.0) {
      k.col(i) = -k.col(i);
      r.row(i) = -r.row(i);
    }
  }
  const double scale = k(2, 2);
  k /= scale;
  Camera camera;
  camera.id = options.camera_id;
  camera.intrinsics.width = options.width;
  camera.intrinsics.height = options.height;
  camera.intrinsics.fx = k(0, 0);
  camera.intrinsics.fy = k(1, 1);
  camera.intrinsics.cx = k(0, 2);
  camera.intrinsics.cy = k(1, 2);
  *skew_px = k(0, 1);
  camera.rotation = r;
  camera.translation = k.inverse() * p4 / scale;
  if (!(camera.intrinsics.fx > 0.0 && camera.intrinsics.fy > 0.0) || !camera.rotation.allFinite()) {
    throw std::invalid_argument("the DLT solution does not describe a camera: check the point correspondences");
  }
  return camera;
}

// Non-linear refinement of pose, focal lengths and principal point (and distortion when asked)
// with the shared KnownPointReprojectionError; the linear camera stays when the solve fails.
void RefineCamera(const std::vector<ControlPoint>& points, const DltOptions& options, Camera* camera) {
  auto pose = PoseBlock(*camera);
  auto intrinsics = IntrinsicsBlock(camera->intrinsics);
  ceres::Problem problem;
  for (const ControlPoint& point : points) {
    problem.AddResidualBlock(KnownPointReprojectionError::Create(point.point_in_world, point.pixel), nullptr,
                             pose.data(), intrinsics.data());
  }
  if (options.refine_distortion) {
    problem.SetManifold(intrinsics.data(), new ceres::SubsetManifold(kIntrinsicsSize, {8}));  // k3 stays 0
  } else {
    problem.SetManifold(intrinsics.data(), new ceres::SubsetManifold(kIntrinsicsSize, {4, 5, 6, 7, 8}));
  }
  ceres::Solver::Options solver_options;
  solver_options.linear_solver_type = ceres::DENSE_QR;
  solver_options.max_num_iterations = 100;
  ceres::Solver::Summary summary;
  ceres::Solve(solver_options, &problem, &summary);
  if (summary.IsSolutionUsable()) {
    SetPoseFromBlock(pose.data(), camera);
    SetIntrinsicsFromBlock(intrinsics.data(), &camera->intrinsics);
  }
}

}  // namespace

void DltOptions::Check() const {
  if (width <= 0 || height <= 0) throw std::invalid_argument("the image size (width, height) must be given");
}

Eigen::Vector2d ProjectDlt(const std::array<double, 11>& l, const Eigen::Vector3d& p) {
  const double denominator = l[8] * p.x() + l[9] * p.y() + l[10] * p.z() + 1.0;
  return Eigen::Vector2d((l[0] * p.x() + l[1] * p.y() + l[2] * p.z() + l[3]) / denominator,
                         (l[4] * p.x() + l[5] * p.y() + l[6] * p.z() + l[7]) / denominator);
}

DltResult CalibrateDlt(const std::vector<ControlPoint>& points, const DltOptions& options) {
  options.Check();
  const Eigen::Matrix<double, 3, 4> p = SolveNormalizedDlt(points);
  DltResult result;
  for (int i = 0; i < 4; ++i) {
    result.parameters[i] = p(0, i);
    result.parameters[4 + i] = p(1, i);
  }
  for (int i = 0; i < 3; ++i) result.parameters[8 + i] = p(2, i);
  double sum = 0.0;
  for (const ControlPoint& point : points) {
    sum += (ProjectDlt(result.parameters, point.point_in_world) - point.pixel).squaredNorm();
  }
  result.linear_rms_px = std::sqrt(sum / static_cast<double>(points.size()));
  result.camera = DecomposeProjection(p, options, &result.skew_px);
  if (options.refine) RefineCamera(points, options, &result.camera);
  result.camera_rms_px = CameraRmsPx(result.camera, points);
  return result;
}

std::vector<ControlPoint> ReadControlPoints(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path + ": cannot open");
  std::vector<ControlPoint> points;
  std::string line;
  int number = 0;
  for (LineRead read; (read = ReadBoundedLine(in, &line, kMaxTextLineBytes)) != LineRead::kEnd;) {
    ++number;
    if (read == LineRead::kTooLong)
      throw std::runtime_error(path + ":" + std::to_string(number) + ": longer than 1 MiB: not a control point file");
    const size_t hash = line.find('#');
    if (hash != std::string::npos) line.resize(hash);
    std::istringstream fields(line);
    double values[5];
    int count = 0;
    double value;
    while (fields >> value) {
      if (count < 5) values[count] = value;
      ++count;
    }
    if (!fields.eof()) {
      throw std::runtime_error(path + ":" + std::to_string(number) + ": not a number");
    }
    if (count == 0) continue;
    if (count != 5) {
      throw std::runtime_error(path + ":" + std::to_string(number) + ": expected 'x y z u v', got " +
                               std::to_string(count) + " values");
    }
    for (double v : values) {
      if (!std::isfinite(v)) throw std::runtime_error(path + ":" + std::to_string(number) + ": value is not finite");
    }
    ControlPoint point;
    point.point_in_world = Eigen::Vector3d(values[0], values[1], values[2]);
    point.pixel = Eigen::Vector2d(values[3], values[4]);
    points.push_back(point);
  }
  return points;
}

}  // namespace mocap

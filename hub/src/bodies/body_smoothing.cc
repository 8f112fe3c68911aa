// A rigid body's orientation refined over neighbouring frames (see body_smoothing.h).
#include "bodies/body_smoothing.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <Eigen/Cholesky>
#include <Eigen/Geometry>

namespace mocap {
namespace {

Eigen::Matrix3d Exp(const Eigen::Vector3d& rotation_vector) {
  const double angle = rotation_vector.norm();
  if (angle < 1e-15) return Eigen::Matrix3d::Identity();
  return Eigen::AngleAxisd(angle, rotation_vector / angle).toRotationMatrix();
}

Eigen::Vector3d Log(const Eigen::Matrix3d& rotation) {
  const Eigen::AngleAxisd aa(rotation);
  return aa.angle() * aa.axis();
}

Eigen::Matrix3d Skew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d s;
  s << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return s;
}

// What one frame's fit tells about its orientation.
struct FrameFit {
  bool usable = false;
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();  // body -> world as fitted
  // Information of the fit's rotation (world-frame rotation vector) per unit point variance:
  // sum of [r]x^T [r]x over its markers' lever arms r about their centroid.
  Eigen::Matrix3d information = Eigen::Matrix3d::Zero();
  Eigen::Vector3d body_centroid = Eigen::Vector3d::Zero();
  Eigen::Vector3d world_centroid = Eigen::Vector3d::Zero();
};

// The chi-square quantile for `dof` degrees of freedom at the normal quantile z (Wilson and
// Hilferty's cube-root approximation, within a few per cent from 3 degrees of freedom up).
double ChiSquareQuantile(double dof, double z) {
  const double c = 2.0 / (9.0 * dof);
  return dof * std::pow(1.0 - c + z * std::sqrt(c), 3.0);
}

}  // namespace

void BodySmoothingOptions::Check() const {
  if (half_window < 0 || half_window > 50) throw std::invalid_argument("body smoothing half window must be 0..50 frames");
  if (degree < 1 || degree > 3) throw std::invalid_argument("body smoothing degree must be 1..3");
  if (!(test_z > 0.0 && test_z < 10.0)) throw std::invalid_argument("body smoothing test quantile must be in (0, 10)");
}

BodySmoothingStats SmoothBodyPoses(const RigidBodyDefinition& body, const std::vector<BodyFrameMarkers>& markers,
                                   std::vector<BodyPose>* poses, const BodySmoothingOptions& options) {
  options.Check();
  if (markers.size() != poses->size()) throw std::invalid_argument("body smoothing: one marker set per pose needed");
  BodySmoothingStats stats;
  const size_t frames = poses->size();
  std::vector<FrameFit> fits(frames);
  double residual_sq = 0.0, residual_dof = 0.0;
  for (size_t f = 0; f < frames; ++f) {
    const BodyPose& pose = (*poses)[f];
    const BodyFrameMarkers& m = markers[f];
    if (!pose.tracked || m.in_body.size() < 3 || m.in_body.size() != m.in_world.size()) continue;
    FrameFit& fit = fits[f];
    fit.rotation = pose.orientation.toRotationMatrix();
    for (size_t i = 0; i < m.in_body.size(); ++i) fit.body_centroid += m.in_body[i], fit.world_centroid += m.in_world[i];
    fit.body_centroid /= static_cast<double>(m.in_body.size());
    fit.world_centroid /= static_cast<double>(m.in_body.size());
    for (size_t i = 0; i < m.in_body.size(); ++i) {
      const Eigen::Matrix3d s = Skew(fit.rotation * (m.in_body[i] - fit.body_centroid));
      fit.information += s.transpose() * s;
      residual_sq += (fit.rotation * m.in_body[i] + pose.position - m.in_world[i]).squaredNorm();
    }
    residual_dof += 3.0 * static_cast<double>(m.in_body.size()) - 6.0;
    // Collinear markers leave a rotation free: no information to weigh that frame by.
    fit.usable = fit.information.determinant() > 1e-9 * std::pow(fit.information.trace(), 3.0);
  }
  for (const FrameFit& fit : fits) stats.unchanged += fit.usable;
  // Per-axis point variance: a rigid fit of N points leaves 3N - 6 degrees of freedom.
  const double variance = residual_dof > 0.0 ? residual_sq / residual_dof : 0.0;
  stats.noise_mm = std::sqrt(variance);
  if (options.half_window == 0 || !(variance > 1e-12)) return stats;  // noiseless: nothing to average

  for (size_t f = 0; f < frames; ++f) {
    if (!fits[f].usable) continue;
    const Eigen::Matrix3d r_f_inverse = fits[f].rotation.transpose();
    const int terms = options.degree + 1;
    const int parameters = 3 * terms;
    for (int k = options.half_window; k >= 1; --k) {
      // Fit phi(t) = sum_p c_p t^p to the frames' rotation vectors phi_j = Log(R_j R_f^-1),
      // t = j - f; phi(0) = c_0 is the refined orientation.
      Eigen::MatrixXd normal = Eigen::MatrixXd::Zero(parameters, parameters);
      Eigen::VectorXd rhs = Eigen::VectorXd::Zero(parameters);
      const size_t first = f >= static_cast<size_t>(k) ? f - static_cast<size_t>(k) : 0;
      const size_t last = std::min(frames - 1, f + static_cast<size_t>(k));
      int used = 0;
      for (size_t j = first; j <= last; ++j) {
        if (!fits[j].usable) continue;
        const double t = static_cast<double>(j) - static_cast<double>(f);
        const Eigen::Matrix3d& w = fits[j].information;
        const Eigen::Vector3d w_phi = w * Log(fits[j].rotation * r_f_inverse);
        for (int p = 0; p < terms; ++p) {
          rhs.segment<3>(3 * p) += std::pow(t, p) * w_phi;
          for (int q = 0; q < terms; ++q) normal.block<3, 3>(3 * p, 3 * q) += std::pow(t, p + q) * w;
        }
        ++used;
      }
      // A fit needs more frames than terms to be tested; smaller windows hold fewer frames.
      if (used <= terms) break;
      const Eigen::LDLT<Eigen::MatrixXd> solver(normal);
      if (solver.info() != Eigen::Success || !solver.isPositive()) continue;
      const Eigen::VectorXd curve = solver.solve(rhs);
      double chi_square = 0.0;
      for (size_t j = first; j <= last; ++j) {
        if (!fits[j].usable) continue;
        const double t = static_cast<double>(j) - static_cast<double>(f);
        Eigen::Vector3d e = Log(fits[j].rotation * r_f_inverse);
        for (int p = 0; p < terms; ++p) e -= std::pow(t, p) * curve.segment<3>(3 * p);
        chi_square += e.dot(fits[j].information * e) / variance;
      }
      if (!(chi_square <= ChiSquareQuantile(3.0 * (used - terms), options.test_z))) continue;
      BodyPose& pose = (*poses)[f];
      const Eigen::Matrix3d rotation = Exp(curve.head<3>()) * fits[f].rotation;
      pose.orientation = Eigen::Quaterniond(rotation).normalized();
      pose.position = fits[f].world_centroid - rotation * fits[f].body_centroid;
      pose.pivot = rotation * body.pivot + pose.position;
      double sum = 0.0;
      for (size_t i = 0; i < markers[f].in_body.size(); ++i)
        sum += (rotation * markers[f].in_body[i] + pose.position - markers[f].in_world[i]).norm();
      pose.mean_error_mm = sum / static_cast<double>(markers[f].in_body.size());
      --stats.unchanged;
      ++(k == options.half_window ? stats.refined : stats.shrunk);
      break;
    }
  }
  return stats;
}

}  // namespace mocap

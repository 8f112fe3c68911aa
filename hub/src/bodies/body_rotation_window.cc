// Rotation fits over several frames, shared by the offline and live estimators (see
// body_rotation_window.h).
#include "bodies/body_rotation_window.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Cholesky>
#include <Eigen/Geometry>

namespace mocap {
namespace {

Eigen::Matrix3d Skew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d s;
  s << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return s;
}

// Farther than this (rad) the logarithm nears its wrap at 180 deg: such frames are left out.
constexpr double kMaxWindowAngle = 1.57;
// The fit's passes (degree >= 2): at most this many, fewer once the curve moves less than
// kSettled rad between passes.
constexpr int kMaxPasses = 6;
constexpr double kSettled = 1e-7;

}  // namespace

double ChiSquareQuantile(double dof, double z) {
  const double c = 2.0 / (9.0 * dof);
  return dof * std::pow(1.0 - c + z * std::sqrt(c), 3.0);
}

Eigen::Matrix3d RotationExp(const Eigen::Vector3d& rotation_vector) {
  const double angle = rotation_vector.norm();
  if (angle < 1e-15) return Eigen::Matrix3d::Identity();
  return Eigen::AngleAxisd(angle, rotation_vector / angle).toRotationMatrix();
}

Eigen::Vector3d RotationLog(const Eigen::Matrix3d& rotation) {
  const Eigen::AngleAxisd aa(rotation);
  return aa.angle() * aa.axis();
}

BodyFrameFit DescribeFrameFit(const BodyPose& pose, const BodyFrameMarkers& m) {
  BodyFrameFit fit;
  if (!pose.tracked || m.in_body.size() < 3 || m.in_body.size() != m.in_world.size()) return fit;
  fit.rotation = pose.orientation.toRotationMatrix();
  for (size_t i = 0; i < m.in_body.size(); ++i) fit.body_centroid += m.in_body[i], fit.world_centroid += m.in_world[i];
  fit.body_centroid /= static_cast<double>(m.in_body.size());
  fit.world_centroid /= static_cast<double>(m.in_body.size());
  for (size_t i = 0; i < m.in_body.size(); ++i) {
    const Eigen::Matrix3d s = Skew(fit.rotation * (m.in_body[i] - fit.body_centroid));
    fit.information += s.transpose() * s;
    fit.residual_sq += (fit.rotation * m.in_body[i] + pose.position - m.in_world[i]).squaredNorm();
  }
  // Per-axis point variance: a rigid fit of N points leaves 3N - 6 degrees of freedom.
  fit.residual_dof = 3.0 * static_cast<double>(m.in_body.size()) - 6.0;
  // Collinear markers leave a rotation free: no information to weigh that frame by.
  fit.usable = fit.information.determinant() > 1e-9 * std::pow(fit.information.trace(), 3.0);
  return fit;
}

RotationCurveFit FitRotationCurve(const std::vector<RotationSample>& samples, const Eigen::Matrix3d& reference,
                                  double max_abs_t, int degree, double variance, double test_z) {
  RotationCurveFit out;
  const int terms = degree + 1;
  const int parameters = 3 * terms;
  // The window ends before the first frame turned more than kMaxWindowAngle from the reference.
  for (const RotationSample& s : samples)
    if (std::abs(s.t) <= max_abs_t && RotationLog(*s.rotation * reference.transpose()).norm() > kMaxWindowAngle)
      max_abs_t = std::abs(s.t) - 1.0;
  long reach = 0;  // the farthest frame from t = 0
  for (const RotationSample& s : samples) {
    if (std::abs(s.t) > max_abs_t) continue;
    ++out.frames;
    reach = std::max(reach, std::lround(std::abs(s.t)));
  }
  if (out.frames <= terms) return out;
  // A steady angular velocity (degree 1) is exactly a line in the tangent space: one pass. Else
  // each pass takes off a share of the previous pass's error in the correction (about a quarter
  // of the angle the window spans: the t^3 term the parabola absorbed), so a few passes, until
  // the curve no longer moves.
  const int passes = degree >= 2 ? kMaxPasses : 1;
  Eigen::Matrix3d ref = reference;
  Eigen::VectorXd curve = Eigen::VectorXd::Zero(parameters);
  // The model's logarithm minus the polynomial, per whole frame t = -reach..reach.
  std::vector<Eigen::Vector3d> departure(static_cast<size_t>(2 * reach + 1), Eigen::Vector3d::Zero());
  auto polynomial = [&](double t) {
    Eigen::Vector3d v = Eigen::Vector3d::Zero();
    for (int p = 1; p < terms; ++p) v += std::pow(t, p) * curve.segment<3>(3 * p);
    return v;
  };
  double chi_square = 0.0;
  for (int pass = 0; pass < passes; ++pass) {
    if (pass > 0) {
      // M(t): the angular velocity w(s) = sum_p p c_p s^(p-1) integrated from 0 both ways in
      // half-frame midpoint steps.
      for (int direction = -1; direction <= 1; direction += 2) {
        Eigen::Matrix3d m = Eigen::Matrix3d::Identity();
        for (long n = 1; n <= reach; ++n) {
          for (int half = 0; half < 2; ++half) {
            const double mid = direction * (static_cast<double>(n - 1) + 0.25 + 0.5 * half);
            Eigen::Vector3d w = Eigen::Vector3d::Zero();
            for (int p = 1; p < terms; ++p) w += p * std::pow(mid, p - 1) * curve.segment<3>(3 * p);
            m = RotationExp(0.5 * direction * w) * m;
          }
          departure[static_cast<size_t>(reach + direction * n)] = RotationLog(m) - polynomial(direction * n);
        }
      }
    }
    Eigen::MatrixXd normal = Eigen::MatrixXd::Zero(parameters, parameters);
    Eigen::VectorXd rhs = Eigen::VectorXd::Zero(parameters);
    const Eigen::Matrix3d ref_inverse = ref.transpose();
    for (const RotationSample& s : samples) {
      if (std::abs(s.t) > max_abs_t) continue;
      const Eigen::Matrix3d& w = *s.information;
      const Eigen::Vector3d phi =
          RotationLog(*s.rotation * ref_inverse) - departure[static_cast<size_t>(reach + std::lround(s.t))];
      const Eigen::Vector3d w_phi = w * phi;
      for (int p = 0; p < terms; ++p) {
        rhs.segment<3>(3 * p) += std::pow(s.t, p) * w_phi;
        for (int q = 0; q < terms; ++q) normal.block<3, 3>(3 * p, 3 * q) += std::pow(s.t, p + q) * w;
      }
    }
    const Eigen::LDLT<Eigen::MatrixXd> solver(normal);
    if (solver.info() != Eigen::Success || !solver.isPositive()) {
      out.outcome = RotationCurveFit::kSingular;
      return out;
    }
    const Eigen::VectorXd previous = curve;
    curve = solver.solve(rhs);
    const bool settled = pass > 0 && curve.head<3>().norm() < kSettled &&
                         (curve - previous).tail(parameters - 3).norm() < kSettled;
    if (pass + 1 < passes && !settled) {
      ref = RotationExp(curve.head<3>()) * ref;
      continue;
    }
    out.covariance_at_zero =
        variance * solver.solve(Eigen::MatrixXd::Identity(parameters, parameters)).topLeftCorner<3, 3>();
    chi_square = 0.0;
    for (const RotationSample& s : samples) {
      if (std::abs(s.t) > max_abs_t) continue;
      Eigen::Vector3d e = RotationLog(*s.rotation * ref_inverse) -
                          departure[static_cast<size_t>(reach + std::lround(s.t))] - curve.head<3>() -
                          polynomial(s.t);
      chi_square += e.dot(*s.information * e) / variance;
    }
    break;
  }
  out.outcome = chi_square <= ChiSquareQuantile(3.0 * (out.frames - terms), test_z) ? RotationCurveFit::kAccepted
                                                                                    : RotationCurveFit::kRejected;
  out.rotation_at_zero = RotationExp(curve.head<3>()) * ref;
  return out;
}

void SetRefinedOrientation(const RigidBodyDefinition& body, const BodyFrameFit& fit, const BodyFrameMarkers& markers,
                           const Eigen::Matrix3d& rotation, BodyPose* pose) {
  pose->orientation = Eigen::Quaterniond(rotation).normalized();
  pose->position = fit.world_centroid - rotation * fit.body_centroid;
  pose->pivot = rotation * body.pivot + pose->position;
  double sum = 0.0;
  for (size_t i = 0; i < markers.in_body.size(); ++i)
    sum += (rotation * markers.in_body[i] + pose->position - markers.in_world[i]).norm();
  pose->mean_error_mm = sum / static_cast<double>(markers.in_body.size());
}

}  // namespace mocap

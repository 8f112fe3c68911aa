// Tsai's linear stages (seed 000 section 3.2, stages 1-5) for one view of control points.
#include "calib/tsai_linear.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include <Eigen/Dense>

#include "calib/tsai_calibration.h"

namespace mocap {
namespace {

// One sign choice of the linear stage, completed with f and tz.
struct Candidate {
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();
  double f = 0.0;
  double agreement = 0.0;  // the seed's sum of x_I x_P + y_I y_P over the points
};

class TsaiLinear {
 public:
  TsaiLinear(const std::vector<ControlPoint>& points, const TsaiCalibrationOptions& options)
      : points_(points), options_(options) {}

  TsaiLinearView Run() {
    Normalise();
    const Candidate linear = LinearStage();
    TsaiLinearView view;
    view.coplanar = coplanar_;
    view.camera = ToTsai(linear.rotation, linear.translation, linear.f);
    return view;
  }

 private:
  // World points centred and scaled (and, for coplanar points, turned so that z = 0), for a
  // well-conditioned linear stage; image points as distorted sensor coordinates (mm).
  void Normalise() {
    const size_t n = points_.size();
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (const ControlPoint& p : points_) mean += p.point_in_world / static_cast<double>(n);
    Eigen::MatrixXd centred(n, 3);
    for (size_t i = 0; i < n; ++i) centred.row(static_cast<Eigen::Index>(i)) = (points_[i].point_in_world - mean).transpose();
    const Eigen::JacobiSVD<Eigen::MatrixXd> svd(centred, Eigen::ComputeThinV);
    const Eigen::Vector3d sigma = svd.singularValues();
    if (!(sigma(1) > 1e-6 * sigma(0)) || !(sigma(0) > 0.0))
      throw std::invalid_argument("the control points are collinear or coincide: spread them over the target");
    coplanar_ = sigma(2) < 1e-6 * sigma(0);
    if (coplanar_) {
      turn_ = svd.matrixV().transpose();  // rows: the plane's axes, then its normal
      if (turn_.determinant() < 0.0) turn_.row(2) *= -1.0;
    }
    offset_ = mean;
    scale_ = std::sqrt(sigma.squaredNorm() / static_cast<double>(n));
    normalised_.resize(n);
    sensor_.resize(n);
    centre_ = Eigen::Vector2d(0.5 * options_.width, 0.5 * options_.height);
    sx_ = coplanar_ ? options_.sx : 1.0;
    const double min_points = coplanar_ ? 5 : 7;
    if (static_cast<double>(n) < min_points)
      throw std::invalid_argument(std::string("Tsai's method needs at least ") + (coplanar_ ? "5 coplanar" : "7") +
                                  " control points, got " + std::to_string(n));
    for (size_t i = 0; i < n; ++i) {
      normalised_[i] = turn_ * (points_[i].point_in_world - mean) / scale_;
      if (coplanar_) normalised_[i].z() = 0.0;
      sensor_[i] = Eigen::Vector2d(options_.pixel_mm * (points_[i].pixel.x() - centre_.x()) / sx_,
                                   options_.pixel_mm * (points_[i].pixel.y() - centre_.y()));
    }
  }

  // Stages 1-5 in the normalised world; the pose comes back in the caller's world.
  Candidate LinearStage() {
    const size_t n = points_.size();
    const int unknowns = coplanar_ ? 6 : 8;
    Eigen::MatrixXd a(n, unknowns);
    for (size_t i = 0; i < n; ++i) {
      const Eigen::Vector3d& x = normalised_[i];
      const double xd = sensor_[i].x(), yd = sensor_[i].y();
      const auto row = static_cast<Eigen::Index>(i);
      if (coplanar_) {
        a.row(row) << yd * x.x(), yd * x.y(), yd, -xd * x.x(), -xd * x.y(), -xd;
      } else {
        a.row(row) << yd * x.x(), yd * x.y(), yd * x.z(), yd, -xd * x.x(), -xd * x.y(), -xd * x.z(), -xd;
      }
    }
    const Eigen::JacobiSVD<Eigen::MatrixXd> svd(a, Eigen::ComputeFullV);
    const Eigen::VectorXd s = svd.singularValues();
    if (!(s(unknowns - 2) > 1e-9 * s(0)))
      throw std::invalid_argument("the radial alignment equations have no unique solution: the points are degenerate "
                                  "(all on one line through the image centre?); use a target that fills the image");
    const Eigen::VectorXd v = svd.matrixV().col(unknowns - 1);
    std::vector<Candidate> candidates;
    if (coplanar_) {
      // Seed 3.2.10: row norms k of [r11 r12 r13] and [r21 r22 r23] from the 2 x 2 block.
      const double r11 = v(0), r12 = v(1), r21 = v(3), r22 = v(4);
      const double sr = r11 * r11 + r12 * r12 + r21 * r21 + r22 * r22;
      const double root = std::sqrt(((r11 - r22) * (r11 - r22) + (r12 + r21) * (r12 + r21)) *
                                    ((r11 + r22) * (r11 + r22) + (r12 - r21) * (r12 - r21)));
      const double k = std::sqrt(0.5 * (sr + root));
      for (double sign : {1.0, -1.0}) {
        const Eigen::VectorXd u = sign * v / k;
        const double r13_sq = std::max(0.0, 1.0 - u(0) * u(0) - u(1) * u(1));
        const double r23_sq = std::max(0.0, 1.0 - u(3) * u(3) - u(4) * u(4));
        // r13 r23 = -(r11 r21 + r12 r22): the product's sign is known, the pair's is not.
        const double product = -(u(0) * u(3) + u(1) * u(4));
        for (double third : {1.0, -1.0}) {
          const double r13 = third * std::sqrt(r13_sq);
          const double r23 = (product >= 0.0 ? 1.0 : -1.0) * third * std::sqrt(r23_sq);
          AddCandidate(Eigen::Vector3d(u(0), u(1), r13), Eigen::Vector3d(u(3), u(4), r23), u(2), u(5), &candidates);
        }
      }
    } else {
      const double row2 = v.segment<3>(4).norm();
      const double s_estimate = v.head<3>().norm() / row2;
      if (!(s_estimate > 0.5 && s_estimate < 2.0))
        throw std::invalid_argument("the x scale factor came out " + std::to_string(s_estimate) +
                                    ": the points do not fit one camera (check the pairing of x y z with u v)");
      sx_ = s_estimate;
      for (Eigen::Vector2d& p : sensor_) p.x() /= sx_;
      for (double sign : {1.0, -1.0}) {
        const Eigen::VectorXd u = sign * v / row2;
        AddCandidate(u.head<3>() / sx_, u.segment<3>(4), u(3) / sx_, u(7), &candidates);
      }
    }
    const Candidate* best = nullptr;
    for (const Candidate& c : candidates) {
      if (c.f > 0.0 && (best == nullptr || c.agreement > best->agreement)) best = &c;
    }
    if (best == nullptr || !(best->agreement > 0.0))
      throw std::invalid_argument("no sign choice puts the points in front of the camera with a positive focal length: "
                                  "check the pairing of x y z with u v");
    // Back to the caller's world: x_cam = scale (R' turn (x - offset) / scale + T').
    Candidate out = *best;
    out.rotation = best->rotation * turn_;
    out.translation = scale_ * best->translation - out.rotation * offset_;
    return out;
  }

  // Stage 4 (orthonormalisation) and 5 (f, tz) for one sign choice, and its agreement.
  void AddCandidate(Eigen::Vector3d row1, Eigen::Vector3d row2, double tx, double ty, std::vector<Candidate>* out) const {
    const double k = -0.5 * row1.dot(row2);
    const Eigen::Vector3d a = row1 + k * row2, b = row2 + k * row1;
    Candidate c;
    c.rotation.row(0) = a.normalized().transpose();
    c.rotation.row(1) = b.normalized().transpose();
    c.rotation.row(2) = a.normalized().cross(b.normalized()).transpose();
    // f and tz from both projection equations: X f - xd tz = w xd, Y f - yd tz = w yd.
    const size_t n = points_.size();
    Eigen::MatrixXd m(2 * n, 2);
    Eigen::VectorXd rhs(2 * n);
    for (size_t i = 0; i < n; ++i) {
      const Eigen::Vector3d& x = normalised_[i];
      const double xc = c.rotation.row(0).dot(x) + tx, yc = c.rotation.row(1).dot(x) + ty;
      const double w = c.rotation.row(2).dot(x);
      const auto r = static_cast<Eigen::Index>(2 * i);
      m.row(r) << xc, -sensor_[i].x();
      rhs(r) = w * sensor_[i].x();
      m.row(r + 1) << yc, -sensor_[i].y();
      rhs(r + 1) = w * sensor_[i].y();
    }
    const Eigen::Vector2d solution = m.colPivHouseholderQr().solve(rhs);
    c.f = solution(0);
    c.translation = Eigen::Vector3d(tx, ty, solution(1));
    if (!std::isfinite(c.f)) return;
    for (size_t i = 0; i < n; ++i) {
      const Eigen::Vector3d cam = c.rotation * normalised_[i] + c.translation;
      if (!(cam.z() > 0.0)) {
        c.agreement = -1.0;
        break;
      }
      const Eigen::Vector2d predicted = c.f * cam.head<2>() / cam.z();
      c.agreement += sensor_[i].dot(predicted);
    }
    out->push_back(c);
  }

  TsaiCamera ToTsai(const Eigen::Matrix3d& rotation, const Eigen::Vector3d& translation, double f) const {
    TsaiCamera t;
    t.ncx = t.nfx = options_.width;
    t.dx = t.dy = t.dpx = t.dpy = options_.pixel_mm;
    t.cx = centre_.x();
    t.cy = centre_.y();
    t.sx = sx_;
    t.f = f;
    t.kappa1 = 0.0;
    t.tx = translation.x();
    t.ty = translation.y();
    t.tz = translation.z();
    t.SetRotation(rotation);
    return t;
  }

  const std::vector<ControlPoint>& points_;
  const TsaiCalibrationOptions& options_;
  bool coplanar_ = false;
  Eigen::Matrix3d turn_ = Eigen::Matrix3d::Identity();
  Eigen::Vector3d offset_ = Eigen::Vector3d::Zero();
  double scale_ = 1.0;
  std::vector<Eigen::Vector3d> normalised_;
  std::vector<Eigen::Vector2d> sensor_;
  Eigen::Vector2d centre_ = Eigen::Vector2d::Zero();
  double sx_ = 1.0;
};

}  // namespace

TsaiLinearView TsaiLinearStage(const std::vector<ControlPoint>& points, const TsaiCalibrationOptions& options) {
  return TsaiLinear(points, options).Run();
}

}  // namespace mocap

// The OpenCV lens model (k1 k2 p1 p2 k3) on normalized image coordinates, in one place: Camera,
// the recon Undistorter and the calibration cost functors all distort through it, so that the
// solver, the simulator and reconstruction can never disagree about the lens.
#pragma once

#include <array>

#include <Eigen/Core>

namespace mocap {

// Distorts normalized coordinates (x, y) with coefficients k = {k1, k2, p1, p2, k3}. Templated
// so that the Ceres functors differentiate the very same expression automatically.
template <typename T>
void DistortNormalized(const T* k, const T& x, const T& y, T* x_distorted, T* y_distorted) {
  const T r2 = x * x + y * y;
  const T radial = T(1.0) + r2 * (k[0] + r2 * (k[1] + r2 * k[4]));
  *x_distorted = x * radial + T(2.0) * k[2] * x * y + k[3] * (r2 + T(2.0) * x * x);
  *y_distorted = y * radial + k[2] * (r2 + T(2.0) * y * y) + T(2.0) * k[3] * x * y;
}

// The same model on doubles, with the analytic 2x2 Jacobian d(distorted)/d(normalized) when
// jacobian is not null (the iterative inverses need it). Inline: the recon Undistorter calls it
// for every blob of every frame, and an out-of-line call there shows in the per-frame time.
inline Eigen::Vector2d DistortNormalized(const std::array<double, 5>& k, const Eigen::Vector2d& normalized,
                                         Eigen::Matrix2d* jacobian = nullptr) {
  const double x = normalized.x(), y = normalized.y();
  Eigen::Vector2d out;
  DistortNormalized(k.data(), x, y, &out.x(), &out.y());
  if (jacobian != nullptr) {
    const double k1 = k[0], k2 = k[1], p1 = k[2], p2 = k[3], k3 = k[4];
    const double r2 = x * x + y * y;
    const double radial = 1.0 + r2 * (k1 + r2 * (k2 + r2 * k3));
    // d(radial)/d(r2), and d(r2)/dx = 2x, d(r2)/dy = 2y.
    const double radial_d = k1 + r2 * (2.0 * k2 + 3.0 * r2 * k3);
    const double xy_term = 2.0 * x * y * radial_d + 2.0 * p1 * x + 2.0 * p2 * y;
    (*jacobian)(0, 0) = radial + 2.0 * x * x * radial_d + 2.0 * p1 * y + 6.0 * p2 * x;
    (*jacobian)(0, 1) = xy_term;
    (*jacobian)(1, 0) = xy_term;
    (*jacobian)(1, 1) = radial + 2.0 * y * y * radial_d + 6.0 * p1 * y + 2.0 * p2 * x;
  }
  return out;
}

}  // namespace mocap

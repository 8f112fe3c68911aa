// Analytic Jacobian of the OpenCV lens model.
#include "geometry/lens.h"

namespace mocap {

Eigen::Vector2d DistortNormalized(const std::array<double, 5>& k, const Eigen::Vector2d& normalized,
                                  Eigen::Matrix2d* jacobian) {
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

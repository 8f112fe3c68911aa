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
// jacobian is not null (the iterative inverses need it; they run on every blob of every frame).
Eigen::Vector2d DistortNormalized(const std::array<double, 5>& k, const Eigen::Vector2d& normalized,
                                  Eigen::Matrix2d* jacobian = nullptr);

}  // namespace mocap

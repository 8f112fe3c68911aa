// RBF interpolation as a linear map of the centre values (see rbf.h).
#include "registration/rbf.h"

#include <cmath>
#include <limits>
#include <stdexcept>

#include <Eigen/QR>

namespace mocap {

std::string RbfKernelName(RbfKernel kernel) { return kernel == RbfKernel::kGaussian ? "gaussian" : "thin-plate"; }

RbfKernel RbfKernelFromName(const std::string& name) {
  if (name == "thin-plate") return RbfKernel::kThinPlate;
  if (name == "gaussian") return RbfKernel::kGaussian;
  throw std::invalid_argument("kernel: '" + name + "' is neither thin-plate nor gaussian");
}

void RbfOptions::Check() const {
  if (!(gaussian_width_mm >= 0.0 && std::isfinite(gaussian_width_mm)))
    throw std::invalid_argument("gaussian_width_mm: " + std::to_string(gaussian_width_mm) +
                                " must be a finite number >= 0 (0: from the centres' spacing)");
  if (!(gaussian_width_scale > 0.0 && std::isfinite(gaussian_width_scale)))
    throw std::invalid_argument("gaussian_width_scale: " + std::to_string(gaussian_width_scale) + " must be > 0");
  if (!(smoothing >= 0.0 && std::isfinite(smoothing)))
    throw std::invalid_argument("smoothing: " + std::to_string(smoothing) + " must be a finite number >= 0");
}

double RbfInterpolator::Kernel(double r) const {
  if (options_.kernel == RbfKernel::kGaussian) return std::exp(-(r / width_) * (r / width_));
  return r > 0.0 ? r * r * std::log(r) : 0.0;
}

RbfInterpolator::RbfInterpolator(const std::vector<Eigen::Vector3d>& centres, const RbfOptions& options)
    : centres_(centres), options_(options) {
  options.Check();
  const size_t n = centres.size();
  if (n < 4) throw std::invalid_argument("RBF: " + std::to_string(n) + " centres; at least 4 are needed");
  double spacing_sum = 0.0;
  for (size_t i = 0; i < n; ++i) {
    double nearest = std::numeric_limits<double>::infinity();
    for (size_t j = 0; j < n; ++j)
      if (j != i) nearest = std::min(nearest, (centres[i] - centres[j]).norm());
    if (!(nearest >= 1e-6))
      throw std::invalid_argument("RBF: centres " + std::to_string(i) + " and another coincide (or are not finite)");
    spacing_sum += nearest;
  }
  width_ = options.gaussian_width_mm > 0.0 ? options.gaussian_width_mm
                                           : options.gaussian_width_scale * spacing_sum / static_cast<double>(n);
  const Eigen::Index size = static_cast<Eigen::Index>(n) + 4;
  Eigen::MatrixXd system = Eigen::MatrixXd::Zero(size, size);
  for (size_t i = 0; i < n; ++i) {
    const Eigen::Index ii = static_cast<Eigen::Index>(i);
    for (size_t j = 0; j < n; ++j) system(ii, static_cast<Eigen::Index>(j)) = Kernel((centres[i] - centres[j]).norm());
    system(ii, ii) += options.smoothing;
    system(ii, static_cast<Eigen::Index>(n)) = system(static_cast<Eigen::Index>(n), ii) = 1.0;
    for (int a = 0; a < 3; ++a)
      system(ii, static_cast<Eigen::Index>(n) + 1 + a) = system(static_cast<Eigen::Index>(n) + 1 + a, ii) = centres[i][a];
  }
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(size, static_cast<Eigen::Index>(n));
  rhs.topRows(static_cast<Eigen::Index>(n)).setIdentity();
  // Centres on one plane (markers on a flat patch) leave the affine part rank-deficient: the
  // minimum-norm solution of the complete orthogonal decomposition still interpolates them.
  solve_ = system.completeOrthogonalDecomposition().solve(rhs);
}

Eigen::MatrixXd RbfInterpolator::Weights(const std::vector<Eigen::Vector3d>& queries) const {
  const Eigen::Index n = static_cast<Eigen::Index>(centres_.size());
  Eigen::MatrixXd basis(static_cast<Eigen::Index>(queries.size()), n + 4);
  for (size_t q = 0; q < queries.size(); ++q) {
    const Eigen::Index qq = static_cast<Eigen::Index>(q);
    for (Eigen::Index i = 0; i < n; ++i) basis(qq, i) = Kernel((queries[q] - centres_[static_cast<size_t>(i)]).norm());
    basis(qq, n) = 1.0;
    basis.block(qq, n + 1, 1, 3) = queries[q].transpose();
  }
  return basis * solve_;
}

Eigen::MatrixXd RbfInterpolator::Interpolate(const std::vector<Eigen::Vector3d>& queries,
                                             const Eigen::MatrixXd& centre_values) const {
  if (centre_values.rows() != static_cast<Eigen::Index>(centres_.size()))
    throw std::invalid_argument("RBF: " + std::to_string(centre_values.rows()) + " values for " +
                                std::to_string(centres_.size()) + " centres");
  return Weights(queries) * centre_values;
}

}  // namespace mocap

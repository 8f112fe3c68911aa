// Radial basis function interpolation of 3D displacements (seed 003, 3.2.2): values known at N
// centres are carried to any point by f(x) = sum_i w_i phi(|x - c_i|) + A x + b, the affine
// part keeping a rigid or uniformly stretched field exact. Two kernels, as the seed compares:
// thin-plate phi(r) = r^2 log r (Duchon's spline, global, grows with r) and Gaussian
// phi(r) = exp(-(r / width)^2) (falls with r; width in mm, by default the mean distance from a
// centre to its nearest other centre times gaussian_width_scale).
// The interpolant is linear in the centre values, so it is kept as a matrix: for query points q,
// values(q) = Weights(q) * values(centres), one matrix product per frame when markers drive a
// mesh. Errors: std::invalid_argument (options, fewer than 4 centres, coincident centres).
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

namespace mocap {

enum class RbfKernel { kThinPlate, kGaussian };

// "thin-plate", "gaussian"; the parser throws std::invalid_argument naming the accepted values.
std::string RbfKernelName(RbfKernel kernel);
RbfKernel RbfKernelFromName(const std::string& name);

struct RbfOptions {
  RbfKernel kernel = RbfKernel::kThinPlate;
  double gaussian_width_mm = 0.0;    // > 0: fixed width; 0: from the centres' spacing
  double gaussian_width_scale = 2.0; // > 0, used when gaussian_width_mm is 0
  // Added to the kernel matrix's diagonal (mm^2 for thin-plate): 0 interpolates exactly; more
  // smooths noisy centres.
  double smoothing = 0.0;

  void Check() const;
};

class RbfInterpolator {
 public:
  // Centres at least 1e-6 mm apart; at least 4 of them.
  RbfInterpolator(const std::vector<Eigen::Vector3d>& centres, const RbfOptions& options);

  // queries x centres: row q holds the weights of every centre's value at query q.
  Eigen::MatrixXd Weights(const std::vector<Eigen::Vector3d>& queries) const;
  // Interpolated values at the queries, from one value (a row) per centre.
  Eigen::MatrixXd Interpolate(const std::vector<Eigen::Vector3d>& queries, const Eigen::MatrixXd& centre_values) const;

  double gaussian_width_mm() const { return width_; }
  size_t NumCentres() const { return centres_.size(); }

 private:
  double Kernel(double r) const;

  std::vector<Eigen::Vector3d> centres_;
  RbfOptions options_;
  double width_ = 0.0;
  // (N + 4) x N: the kernel weights and affine coefficients that a column of centre values gives.
  Eigen::MatrixXd solve_;
};

}  // namespace mocap

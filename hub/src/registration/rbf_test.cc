// RBF interpolation: exact at the centres, affine fields reproduced everywhere (the polynomial
// part), a smooth field followed between centres, both kernels; refusals.
#include "registration/rbf.h"

#include <cmath>
#include <random>
#include <stdexcept>

#include <gtest/gtest.h>

namespace mocap {
namespace {

std::vector<Eigen::Vector3d> Grid(double step, double jitter, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> noise(-jitter, jitter);
  std::vector<Eigen::Vector3d> points;
  for (double x = -100; x <= 100; x += step)
    for (double y = -100; y <= 100; y += step)
      points.emplace_back(x + noise(rng), y + noise(rng), 0.002 * (x * x - y * y) + noise(rng));
  return points;
}

Eigen::MatrixXd Field(const std::vector<Eigen::Vector3d>& points, Eigen::Vector3d (*f)(const Eigen::Vector3d&)) {
  Eigen::MatrixXd values(static_cast<Eigen::Index>(points.size()), 3);
  for (size_t i = 0; i < points.size(); ++i) values.row(static_cast<Eigen::Index>(i)) = f(points[i]).transpose();
  return values;
}

Eigen::Vector3d Affine(const Eigen::Vector3d& p) {
  Eigen::Matrix3d a;
  a << 0.1, -0.2, 0.05, 0.3, 0.02, -0.1, 0.0, 0.15, 0.2;
  return a * p + Eigen::Vector3d(5, -3, 2);
}

Eigen::Vector3d Smooth(const Eigen::Vector3d& p) {
  return Eigen::Vector3d(3 * std::sin(p.x() / 60.0), 2 * std::cos(p.y() / 70.0), 4 * std::exp(-p.squaredNorm() / 8000.0));
}

TEST(Rbf, BothKernelsInterpolateCentresAndAffineFieldsExactly) {
  const std::vector<Eigen::Vector3d> centres = Grid(40.0, 8.0, 1);
  const std::vector<Eigen::Vector3d> queries = Grid(13.0, 5.0, 2);
  for (RbfKernel kernel : {RbfKernel::kThinPlate, RbfKernel::kGaussian}) {
    RbfOptions options;
    options.kernel = kernel;
    const RbfInterpolator rbf(centres, options);
    const Eigen::MatrixXd at_centres = rbf.Interpolate(centres, Field(centres, Smooth));
    EXPECT_LT((at_centres - Field(centres, Smooth)).cwiseAbs().maxCoeff(), 1e-6) << RbfKernelName(kernel);
    const Eigen::MatrixXd affine = rbf.Interpolate(queries, Field(centres, Affine));
    EXPECT_LT((affine - Field(queries, Affine)).cwiseAbs().maxCoeff(), 1e-6) << RbfKernelName(kernel);
    // Weights carry a constant value unchanged: every row sums to one.
    const Eigen::MatrixXd weights = rbf.Weights(queries);
    EXPECT_LT((weights.rowwise().sum().array() - 1.0).abs().maxCoeff(), 1e-8);
  }
}

TEST(Rbf, SmoothFieldFollowedBetweenCentresAndBetterWithDenserCentres) {
  // Queries between the centres, not beyond them: every grid spans at least -100..80 mm.
  std::vector<Eigen::Vector3d> queries;
  for (const Eigen::Vector3d& q : Grid(11.0, 3.0, 3))
    if (std::abs(q.x()) < 75 && std::abs(q.y()) < 75) queries.push_back(q);
  for (RbfKernel kernel : {RbfKernel::kThinPlate, RbfKernel::kGaussian}) {
    RbfOptions options;
    options.kernel = kernel;
    double previous = INFINITY;
    for (double step : {50.0, 30.0, 20.0}) {
      const std::vector<Eigen::Vector3d> centres = Grid(step, 2.0, 4);
      const Eigen::MatrixXd error =
          RbfInterpolator(centres, options).Interpolate(queries, Field(centres, Smooth)) - Field(queries, Smooth);
      const double rms = std::sqrt(error.rowwise().squaredNorm().mean());
      EXPECT_LT(rms, previous) << RbfKernelName(kernel) << " " << step;
      previous = rms;
    }
    EXPECT_LT(previous, 0.05) << RbfKernelName(kernel);
  }
}

TEST(Rbf, GaussianWidthFollowsSpacingUnlessGiven) {
  const std::vector<Eigen::Vector3d> centres = Grid(40.0, 0.0, 5);
  RbfOptions options;
  options.kernel = RbfKernel::kGaussian;
  EXPECT_NEAR(RbfInterpolator(centres, options).gaussian_width_mm(), 80.0, 1.0);
  options.gaussian_width_mm = 25.0;
  EXPECT_EQ(RbfInterpolator(centres, options).gaussian_width_mm(), 25.0);
}

TEST(Rbf, Refusals) {
  std::vector<Eigen::Vector3d> centres = Grid(100.0, 0.0, 6);
  EXPECT_THROW(RbfInterpolator(std::vector<Eigen::Vector3d>(centres.begin(), centres.begin() + 3), RbfOptions{}),
               std::invalid_argument);
  centres.push_back(centres.front());
  EXPECT_THROW(RbfInterpolator(centres, RbfOptions{}), std::invalid_argument);
  EXPECT_THROW(RbfKernelFromName("cubic"), std::invalid_argument);
  EXPECT_EQ(RbfKernelFromName(RbfKernelName(RbfKernel::kGaussian)), RbfKernel::kGaussian);
  RbfOptions options;
  options.smoothing = -1.0;
  EXPECT_THROW(options.Check(), std::invalid_argument);
}

}  // namespace
}  // namespace mocap

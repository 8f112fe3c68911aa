// The shared lens model: analytic Jacobian against finite differences, the templated and the
// double form agree, and zero coefficients leave coordinates untouched.
#include "geometry/lens.h"

#include <gtest/gtest.h>

namespace mocap {
namespace {

const std::array<double, 5> kBarrel = {-0.28, 0.09, 0.0008, -0.0005, -0.012};

TEST(Lens, JacobianMatchesFiniteDifferences) {
  const Eigen::Vector2d p(0.31, -0.22);
  Eigen::Matrix2d jacobian;
  DistortNormalized(kBarrel, p, &jacobian);
  const double h = 1e-7;
  for (int k = 0; k < 2; ++k) {
    Eigen::Vector2d step = Eigen::Vector2d::Zero();
    step[k] = h;
    const Eigen::Vector2d numeric =
        (DistortNormalized(kBarrel, p + step) - DistortNormalized(kBarrel, p - step)) / (2 * h);
    EXPECT_LT((numeric - jacobian.col(k)).norm(), 1e-7);
  }
}

TEST(Lens, TemplatedFormMatchesJacobianForm) {
  const Eigen::Vector2d p(-0.4, 0.17);
  double x = 0.0, y = 0.0;
  DistortNormalized(kBarrel.data(), p.x(), p.y(), &x, &y);
  Eigen::Matrix2d unused;
  EXPECT_EQ(Eigen::Vector2d(x, y), DistortNormalized(kBarrel, p, &unused));
  EXPECT_GT((Eigen::Vector2d(x, y) - p).norm(), 0.02);
}

TEST(Lens, ZeroCoefficientsAreIdentity) {
  const Eigen::Vector2d p(0.25, 0.5);
  Eigen::Matrix2d jacobian;
  EXPECT_EQ(DistortNormalized({0, 0, 0, 0, 0}, p, &jacobian), p);
  EXPECT_LT((jacobian - Eigen::Matrix2d::Identity()).norm(), 1e-15);
}

}  // namespace
}  // namespace mocap

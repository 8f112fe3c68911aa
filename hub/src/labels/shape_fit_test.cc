// Upright similarity fit: recovers a known turn, scale and shift; the scale is kept in range.
#include <cmath>

#include <gtest/gtest.h>

#include "labels/shape_fit.h"

namespace mocap {
namespace {

TEST(ShapeFit, RecoversTurnScaleAndShift) {
  UprightTransform truth;
  truth.yaw = 2.5, truth.scale = 1.1, truth.translation = Eigen::Vector3d(100, -50, 900);
  std::vector<Eigen::Vector3d> source = {{0, 0, 0}, {200, 0, 50}, {0, 150, 400}, {-80, 30, 1600}, {60, -90, -700}};
  std::vector<Eigen::Vector3d> target;
  for (const auto& p : source) target.push_back(truth.Apply(p));
  const UprightTransform fit = FitUpright(source, target, true);
  EXPECT_NEAR(fit.yaw, 2.5, 1e-9);
  EXPECT_NEAR(fit.scale, 1.1, 1e-9);
  EXPECT_TRUE(fit.translation.isApprox(truth.translation, 1e-9));
  const UprightTransform rigid = FitUpright(source, target, false);
  EXPECT_DOUBLE_EQ(rigid.scale, 1.0);
  EXPECT_NEAR(rigid.yaw, 2.5, 1e-9);
}

TEST(ShapeFit, ScaleStaysInRange) {
  std::vector<Eigen::Vector3d> source = {{0, 0, 0}, {100, 0, 0}, {0, 100, 100}};
  std::vector<Eigen::Vector3d> target;
  for (const auto& p : source) target.push_back(3.0 * p);
  EXPECT_DOUBLE_EQ(FitUpright(source, target, true).scale, 1.35);
}

}  // namespace
}  // namespace mocap

// Constant-velocity Kalman filter: converges on linear motion, smooths noise, grows uncertainty.
#include "track/kalman.h"

#include <random>

#include <gtest/gtest.h>

namespace mocap {
namespace {

TEST(ConstantVelocityKalman, LearnsVelocityOfLinearMotion) {
  const Eigen::Vector3d start(10, 20, 30), velocity(500, -300, 100);  // mm/s
  ConstantVelocityKalman filter(start, KalmanOptions());
  const double dt = 0.01;
  for (int k = 1; k <= 50; ++k) {
    filter.Predict(dt);
    filter.Update(start + velocity * k * dt, 0.5);
  }
  EXPECT_LT((filter.velocity() - velocity).norm(), 1.0);
  filter.Predict(dt);
  EXPECT_LT((filter.position() - (start + velocity * 51 * dt)).norm(), 0.05);
}

TEST(ConstantVelocityKalman, FiltersMeasurementNoise) {
  std::mt19937 rng(1);
  std::normal_distribution<double> noise(0.0, 2.0);
  KalmanOptions options;
  options.acceleration_noise = 100.0;  // nearly uniform motion
  const Eigen::Vector3d velocity(200, 0, 0);
  ConstantVelocityKalman filter(Eigen::Vector3d::Zero(), options);
  double raw = 0.0, filtered = 0.0;
  for (int k = 1; k <= 400; ++k) {
    filter.Predict(0.01);
    const Eigen::Vector3d truth = velocity * k * 0.01;
    const Eigen::Vector3d measured = truth + Eigen::Vector3d(noise(rng), noise(rng), noise(rng));
    filter.Update(measured, 2.0);
    if (k > 100) {
      raw += (measured - truth).squaredNorm();
      filtered += (filter.position() - truth).squaredNorm();
    }
  }
  EXPECT_LT(filtered, 0.3 * raw);
}

TEST(ConstantVelocityKalman, UncertaintyGrowsWithoutMeasurements) {
  ConstantVelocityKalman filter(Eigen::Vector3d::Zero(), KalmanOptions());
  for (int k = 0; k < 10; ++k) {
    filter.Predict(0.01);
    filter.Update(Eigen::Vector3d::Zero(), 0.5);
  }
  const double settled = filter.PositionStd();
  filter.Predict(0.01);
  const double one = filter.PositionStd();
  filter.Predict(0.01);
  EXPECT_GT(one, settled);
  EXPECT_GT(filter.PositionStd(), one);
  EXPECT_GT(filter.InnovationStd(1.0), filter.PositionStd());
}

}  // namespace
}  // namespace mocap

// Constant-velocity Kalman filter with a covariance shared by the three axes.
#include "track/kalman.h"

#include <cmath>

namespace mocap {

ConstantVelocityKalman::ConstantVelocityKalman(const Eigen::Vector3d& position,
                                               const KalmanOptions& options)
    : position_(position), acceleration_noise_(options.acceleration_noise) {
  covariance_ << options.measurement_noise_mm * options.measurement_noise_mm, 0.0, 0.0,
      options.initial_velocity_std * options.initial_velocity_std;
}

void ConstantVelocityKalman::Restart(const Eigen::Vector3d& position, const Eigen::Vector3d& velocity,
                                     const KalmanOptions& options) {
  *this = ConstantVelocityKalman(position, options);
  velocity_ = velocity;
}

void ConstantVelocityKalman::Predict(double dt) {
  position_ += dt * velocity_;
  Eigen::Matrix2d transition;
  transition << 1.0, dt, 0.0, 1.0;
  // Discrete white-noise acceleration: Q = q [dt^4/4 dt^3/2; dt^3/2 dt^2].
  const double q = acceleration_noise_ * acceleration_noise_;
  Eigen::Matrix2d process;
  process << 0.25 * dt * dt * dt * dt, 0.5 * dt * dt * dt, 0.5 * dt * dt * dt, dt * dt;
  covariance_ = transition * covariance_ * transition.transpose() + q * process;
}

void ConstantVelocityKalman::Update(const Eigen::Vector3d& measured, double measurement_noise_mm) {
  const double innovation_variance = covariance_(0, 0) + measurement_noise_mm * measurement_noise_mm;
  const double gain_p = covariance_(0, 0) / innovation_variance;
  const double gain_v = covariance_(1, 0) / innovation_variance;
  const Eigen::Vector3d innovation = measured - position_;
  position_ += gain_p * innovation;
  velocity_ += gain_v * innovation;
  // P = (I - K H) P, written out for the 2x2 case.
  const Eigen::Matrix2d prior = covariance_;
  covariance_(0, 0) = (1.0 - gain_p) * prior(0, 0);
  covariance_(0, 1) = (1.0 - gain_p) * prior(0, 1);
  covariance_(1, 0) = covariance_(0, 1);
  covariance_(1, 1) = prior(1, 1) - gain_v * prior(0, 1);
}

double ConstantVelocityKalman::PositionStd() const { return std::sqrt(covariance_(0, 0)); }

double ConstantVelocityKalman::InnovationStd(double measurement_noise_mm) const {
  return std::sqrt(covariance_(0, 0) + measurement_noise_mm * measurement_noise_mm);
}

}  // namespace mocap

// Constant-velocity Kalman filter of one marker (seed 001 section 4.1): state [p v], F = [I dt I;
// 0 I], H = [I 0], white-noise acceleration. The three axes share H, F, Q and R and are always
// measured together, so they share one 2x2 covariance: the 6x6 filter collapses to three 2-state
// filters with a single covariance update, exactly equivalent and about ten times cheaper.
#pragma once

#include <Eigen/Core>

#include "track/track_options.h"

namespace mocap {

class ConstantVelocityKalman {
 public:
  ConstantVelocityKalman() = default;
  ConstantVelocityKalman(const Eigen::Vector3d& position, const KalmanOptions& options);

  // Time update (eq. 10, 13) over dt seconds.
  void Predict(double dt);
  // Measurement update (eqs. 14-16) with the given measurement noise (mm, one sigma).
  void Update(const Eigen::Vector3d& measured, double measurement_noise_mm);

  // Restarts the filter at a measured position with a given velocity (mm/s), keeping the
  // uncertainty of a fresh track: for a measurement that the filter's own prediction missed.
  void Restart(const Eigen::Vector3d& position, const Eigen::Vector3d& velocity,
               const KalmanOptions& options);

  const Eigen::Vector3d& position() const { return position_; }
  const Eigen::Vector3d& velocity() const { return velocity_; }  // mm/s
  // One-sigma uncertainty of the predicted position per axis, and of the innovation.
  double PositionStd() const;
  double InnovationStd(double measurement_noise_mm) const;

 private:
  Eigen::Vector3d position_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d velocity_ = Eigen::Vector3d::Zero();
  Eigen::Matrix2d covariance_ = Eigen::Matrix2d::Identity();  // [pp pv; vp vv], per axis
  double acceleration_noise_ = 1.0;
};

}  // namespace mocap

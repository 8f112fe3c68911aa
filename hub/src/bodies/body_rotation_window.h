// The pieces shared by the offline refinement (body_smoothing.h, frames from both sides) and the
// live estimator (body_live_filter.h, past frames only) of a rigid body's orientation:
// - what one frame's fit says about its rotation: the information of its world-frame rotation
//   vector per unit point variance (its markers' lever arms about their centroid) and its
//   residual, from which the point noise is estimated;
// - a polynomial in time fitted to several frames' rotation vectors in the tangent space at a
//   reference frame (t = 0), each frame weighted by its information, and the chi-square test of
//   the frames against that polynomial that says whether the motion agrees with the model;
// - a pose rewritten with a refined orientation, keeping the frame's measured marker centroid.
// Pure: no I/O, no state. Errors: none (a fit that cannot be made says so in its result).
#pragma once

#include <vector>

#include <Eigen/Core>

#include "bodies/body_definition.h"
#include "bodies/body_tracker.h"

namespace mocap {

// One body at one frame: the markers its fit used (body frame) and their points (world, mm).
struct BodyFrameMarkers {
  std::vector<Eigen::Vector3d> in_body;
  std::vector<Eigen::Vector3d> in_world;
};

// What one frame's fit tells about its orientation.
struct BodyFrameFit {
  bool usable = false;  // fitted, >= 3 markers not on one line
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();  // body -> world as fitted
  // Information of the fit's rotation (world-frame rotation vector) per unit point variance:
  // sum of [r]x^T [r]x over its markers' lever arms r about their centroid.
  Eigen::Matrix3d information = Eigen::Matrix3d::Zero();
  Eigen::Vector3d body_centroid = Eigen::Vector3d::Zero();
  Eigen::Vector3d world_centroid = Eigen::Vector3d::Zero();
  double residual_sq = 0.0;  // sum of squared marker distances from the fit, mm^2
  double residual_dof = 0.0;  // 3N - 6 for N markers
};

// The fit of `pose` to `markers` (not usable unless the pose is tracked with >= 3 markers whose
// lever arms pin all three rotation axes).
BodyFrameFit DescribeFrameFit(const BodyPose& pose, const BodyFrameMarkers& markers);

// One frame in a window: its time from the reference frame (frames, whole numbers), its fitted
// rotation and its information.
struct RotationSample {
  double t = 0.0;
  const Eigen::Matrix3d* rotation = nullptr;
  const Eigen::Matrix3d* information = nullptr;
};

struct RotationCurveFit {
  enum Outcome { kTooFewFrames, kSingular, kRejected, kAccepted };
  Outcome outcome = kTooFewFrames;
  Eigen::Matrix3d rotation_at_zero = Eigen::Matrix3d::Identity();  // the curve at t = 0 (when accepted)
  Eigen::Matrix3d covariance_at_zero = Eigen::Matrix3d::Zero();    // of its rotation vector, rad^2
  int frames = 0;                                                   // samples used
};

// Fits the samples with |t| <= max_abs_t a rotation R(t) = M(t) R(0) whose world-frame angular
// velocity is a polynomial of degree - 1 in time (degree 2: steady angular acceleration), each
// frame weighted by its information over `variance` (the point noise per axis, mm^2), and tests
// the frames' deviations from it: chi-square over 3 (frames - terms) degrees of freedom at the
// one-sided normal quantile `test_z`. A fit needs more frames than terms to be tested.
// The fit is the polynomial phi(t) = sum_p c_p t^p (p <= degree) in the tangent space at the
// reference (Log(R_j R_ref^-1)), corrected for what that polynomial misses of the rotation M(t)
// (for an angular velocity that turns, M's logarithm has a t^3 term, -(w x a) t^3 / 12 to first
// order, the Magnus expansion's second term: over a one-sided window that is the bias that
// matters), by a few fixed-point steps: M(t) integrated from the current coefficients, its
// logarithm's departure from the polynomial taken off the samples, the reference moved to the
// fit's value at t = 0, and fitted again. `reference` is the frame at t = 0's own rotation.
RotationCurveFit FitRotationCurve(const std::vector<RotationSample>& samples, const Eigen::Matrix3d& reference,
                                  double max_abs_t, int degree, double variance, double test_z);

Eigen::Matrix3d RotationExp(const Eigen::Vector3d& rotation_vector);
Eigen::Vector3d RotationLog(const Eigen::Matrix3d& rotation);

// The chi-square quantile for `dof` degrees of freedom at the one-sided normal quantile z
// (Wilson and Hilferty's cube-root approximation, within a few per cent from 3 degrees of
// freedom up).
double ChiSquareQuantile(double dof, double z);

// Rewrites `pose` with orientation `rotation`: the position keeps the frame's measured marker
// centroid (x = centroid - R * body centroid), the pivot and the mean marker error follow.
void SetRefinedOrientation(const RigidBodyDefinition& body, const BodyFrameFit& fit, const BodyFrameMarkers& markers,
                           const Eigen::Matrix3d& rotation, BodyPose* pose);

}  // namespace mocap

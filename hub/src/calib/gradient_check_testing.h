// For the tests of the calibration's cost functions: their automatic Jacobians checked against
// numeric ones (ceres::GradientChecker) with a first step that is small against the scene.
//
// GradientChecker differentiates numerically by Ridders' method, whose first step is
// max(1, |parameter|) x ridders_relative_initial_step_size x shrink^(extrapolations / 2), i.e. 32 x
// the relative step by default, then shrinks. The residual is smooth only well inside the point's
// depth (the projection divides by it), but the pose's translation is the world origin in camera
// coordinates: metres, unrelated to that depth. At ceres' default of 1e-2 a translation of 4.2 m
// starts Ridders at 1.33 m for a point 2.35 m deep, where the tableau cannot converge: its
// estimate was 0.65 % off the automatic Jacobian, which plain central differences at every step
// from 1e-4 to 1 mm agree with to 1e-6. The same default swings a rotation by up to 1 rad and a
// wand's unit axis by 0.32 (80 mm at a 250 mm offset): over 2000 random scenes 29 % of the checks
// failed (cost_functions_test). 5e-5 keeps every first step below 2 % of the depth even for a
// point 1 m deep seen by a camera 8.5 m from the world origin (13.6 mm; 1e-4, 27 mm, did not),
// which each check asserts for its configuration, so that it stays sound on any scene.
#pragma once

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <ceres/gradient_checker.h>
#include <ceres/manifold.h>
#include <gtest/gtest.h>

namespace mocap::testing {

constexpr double kRiddersRelativeStep = 5e-5;
constexpr double kRiddersStartFactor = 32.0;  // shrink factor 2 ^ (10 extrapolations / 2)

// The first step Ridders takes on a parameter of this value (ceres never steps by less than the
// relative step itself).
inline double RiddersFirstStep(double parameter) {
  return kRiddersRelativeStep * kRiddersStartFactor * std::max(1.0, std::abs(parameter));
}

// The check with kRiddersRelativeStep. first_step_mm: the farthest the first step of any
// parameter moves the projected point (in mm, in camera coordinates), computed by the caller
// from RiddersFirstStep; it must stay under 2 % of the point's depth_mm. `what` names the
// configuration in the failure.
//
// Each derivative is compared relative to the largest of its parameter's derivatives (its column
// of the Jacobian), not to itself as ceres' own verdict does: over thousands of random scenes
// some derivative is near zero by chance (a residual's row barely moved by one translation),
// and a difference of roundoff (1e-11) is then a relative error over 1e-6 that says nothing
// about the Jacobian. A wrong derivative is off by a fraction of its column's size.
inline ::testing::AssertionResult GradientsMatchNumeric(const ceres::CostFunction& cost,
                                                        const std::vector<const ceres::Manifold*>* manifolds,
                                                        const double* const* parameters, double first_step_mm,
                                                        double depth_mm, const std::string& what) {
  constexpr double kRelativePrecision = 1e-6;
  if (!(first_step_mm < 0.02 * depth_mm)) {
    return ::testing::AssertionFailure() << what << ": the first numeric step moves the point " << first_step_mm
                                         << " mm at a depth of " << depth_mm << " mm (over 2 %)";
  }
  ceres::NumericDiffOptions numeric;
  numeric.ridders_relative_initial_step_size = kRiddersRelativeStep;
  ceres::GradientChecker checker(&cost, manifolds, numeric);
  ceres::GradientChecker::ProbeResults results;
  if (checker.Probe(parameters, kRelativePrecision, &results)) return ::testing::AssertionSuccess();
  if (!results.return_value) return ::testing::AssertionFailure() << what << ": the cost function failed";
  // Probe's other reasons to fail: residuals that differ with and without Jacobians.
  std::vector<double> residuals(static_cast<size_t>(cost.num_residuals()));
  if (!cost.Evaluate(parameters, residuals.data(), nullptr)) {
    return ::testing::AssertionFailure() << what << ": the cost function failed without Jacobians";
  }
  for (size_t i = 0; i < residuals.size(); ++i) {
    // Jets round differently from doubles in the last bits.
    const double with_jacobians = results.residuals(static_cast<Eigen::Index>(i));
    if (!(std::abs(residuals[i] - with_jacobians) <= 1e-9 * std::max(1.0, std::abs(residuals[i])))) {
      return ::testing::AssertionFailure() << what << ": residual " << i << " differs with Jacobians";
    }
  }
  double worst = 0.0;
  for (size_t block = 0; block < results.local_jacobians.size(); ++block) {
    const ceres::Matrix& automatic = results.local_jacobians[block];
    const ceres::Matrix& numeric_jacobian = results.local_numeric_jacobians[block];
    for (Eigen::Index column = 0; column < automatic.cols(); ++column) {
      const double scale = std::max(automatic.col(column).cwiseAbs().maxCoeff(),
                                    numeric_jacobian.col(column).cwiseAbs().maxCoeff());
      const double error = (automatic.col(column) - numeric_jacobian.col(column)).cwiseAbs().maxCoeff();
      if (error > 0.0) worst = std::max(worst, scale > 0.0 ? error / scale : HUGE_VAL);
    }
  }
  if (worst > kRelativePrecision) {
    return ::testing::AssertionFailure() << what << ": a derivative is off by " << worst
                                         << " of its parameter's largest derivative\n"
                                         << results.error_log;
  }
  return ::testing::AssertionSuccess();
}

}  // namespace mocap::testing

// Repeated calibrations: copies of one rig in different world frames have no spread after the
// alignment and their mean is the truth; a camera whose centre and rotation alternate by known
// amounts shows exactly that mean and standard deviation; too few calibrations are refused.
#include "eval/calibration_repeatability.h"

#include <cmath>
#include <stdexcept>
#include <vector>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

namespace mocap {
namespace {

Rig TruthRig() {
  Rig rig;
  for (int i = 0; i < 6; ++i) {
    Camera camera;
    camera.id = static_cast<uint32_t>(10 + i);
    camera.intrinsics.fx = camera.intrinsics.fy = 1000.0;
    const double angle = i * M_PI / 3.0;
    const Eigen::Vector3d centre(4000.0 * std::cos(angle), 4000.0 * std::sin(angle), 2000.0 + 300.0 * (i % 2));
    camera.rotation = Eigen::AngleAxisd(angle + 0.3, Eigen::Vector3d(0.1, 0.2, 1.0).normalized()).toRotationMatrix();
    camera.translation = -camera.rotation * centre;
    rig.cameras.push_back(camera);
  }
  return rig;
}

// The same cameras described in another world frame: world_b = rotation * world_a + translation.
Rig MoveWorld(const Rig& rig, const Eigen::Matrix3d& rotation, const Eigen::Vector3d& translation) {
  Rig moved = rig;
  for (Camera& camera : moved.cameras) {
    const Eigen::Vector3d centre = rotation * camera.CenterInWorld() + translation;
    camera.rotation = camera.rotation * rotation.transpose();
    camera.translation = -camera.rotation * centre;
  }
  return moved;
}

TEST(CalibrationRepeatabilityTest, RigidCopiesHaveNoSpreadAndTheirMeanIsTheTruth) {
  const Rig truth = TruthRig();
  std::vector<Rig> calibrations;
  for (int k = 0; k < 5; ++k) {
    const Eigen::Matrix3d r = Eigen::AngleAxisd(0.3 * k, Eigen::Vector3d(1.0, -0.5, 0.2).normalized()).toRotationMatrix();
    calibrations.push_back(MoveWorld(truth, r, Eigen::Vector3d(100.0 * k, -50.0, 7.0 * k)));
  }
  const CalibrationRepeatability r = EvaluateRepeatability(calibrations, &truth, true);
  ASSERT_EQ(r.cameras.size(), truth.cameras.size());
  for (const CameraRepeatability& c : r.cameras) {
    EXPECT_EQ(c.calibrations, 5u);
    EXPECT_LT(c.centre_spread_mm, 1e-6);
    EXPECT_LT(c.rotation_spread_deg, 1e-6);
    EXPECT_LT(c.centre_bias_mm, 1e-6);
    EXPECT_LT(c.rotation_bias_deg, 1e-6);
  }
  // Without alignment the world frames differ, and the spread says so.
  EXPECT_GT(EvaluateRepeatability(calibrations, &truth, false).centre_spread_max_mm, 10.0);
}

TEST(CalibrationRepeatabilityTest, KnownScatterGivesItsMeanAndStandardDeviation) {
  const Rig truth = TruthRig();
  std::vector<Rig> calibrations;
  const double d = 2.0, angle_deg = 0.1;
  for (int k = 0; k < 10; ++k) {
    Rig rig = truth;
    Camera& camera = rig.cameras[2];
    const double sign = k % 2 == 0 ? 1.0 : -1.0;
    const Eigen::Vector3d centre = camera.CenterInWorld() + Eigen::Vector3d(sign * d, 0.0, 0.0);
    // Turned about the camera's own y axis (world_from_cam * R_y).
    const Eigen::Matrix3d world_from_cam =
        camera.rotation.transpose() * Eigen::AngleAxisd(sign * angle_deg * M_PI / 180.0, Eigen::Vector3d::UnitY()).toRotationMatrix();
    camera.rotation = world_from_cam.transpose();
    camera.translation = -camera.rotation * centre;
    calibrations.push_back(rig);
  }
  const CalibrationRepeatability r = EvaluateRepeatability(calibrations, &truth, false);
  const CameraRepeatability& c = r.cameras[2];
  const double n = 10.0;
  EXPECT_NEAR(c.centre_std_mm.x(), d * std::sqrt(n / (n - 1.0)), 1e-9);
  EXPECT_NEAR(c.centre_std_mm.y(), 0.0, 1e-9);
  EXPECT_NEAR(c.centre_spread_mm, d, 1e-9);
  EXPECT_NEAR(c.centre_bias_mm, 0.0, 1e-9);
  EXPECT_NEAR(c.rotation_std_deg.y(), angle_deg * std::sqrt(n / (n - 1.0)), 1e-9);
  EXPECT_NEAR(c.rotation_std_deg.x(), 0.0, 1e-9);
  EXPECT_NEAR(c.rotation_std_deg.z(), 0.0, 1e-9);
  EXPECT_NEAR(c.rotation_spread_deg, angle_deg, 1e-9);
  EXPECT_NEAR(c.rotation_bias_deg, 0.0, 1e-9);
  EXPECT_NEAR(r.centre_spread_max_mm, d, 1e-9);
  EXPECT_LT(r.cameras[0].centre_spread_mm, 1e-9);  // the other cameras did not move
  // Without a truth the first calibration is the reference: the mean is still the middle.
  const CalibrationRepeatability own = EvaluateRepeatability(calibrations, nullptr, false);
  EXPECT_NEAR((own.cameras[2].centre_mean_mm - truth.cameras[2].CenterInWorld()).norm(), 0.0, 1e-9);
  EXPECT_TRUE(std::isnan(own.cameras[2].centre_bias_mm));
}

TEST(CalibrationRepeatabilityTest, RefusesTooFewCalibrationsOrSharedCameras) {
  const Rig truth = TruthRig();
  EXPECT_THROW(EvaluateRepeatability({truth}, nullptr, true), std::invalid_argument);
  Rig two;
  two.cameras = {truth.cameras[0], truth.cameras[1]};
  EXPECT_THROW(EvaluateRepeatability({truth, two}, nullptr, true), std::invalid_argument);
  Rig other = truth;
  for (Camera& camera : other.cameras) camera.id += 100;
  EXPECT_THROW(EvaluateRepeatability({truth, other}, &truth, false), std::invalid_argument);
}

}  // namespace
}  // namespace mocap

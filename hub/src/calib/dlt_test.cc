// DLT: exact recovery from noiseless control points, noise-level residuals with noise, lens
// refinement, refusal of too few or coplanar points, and the control point reader.
#include "calib/dlt.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <stdexcept>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "simcore/test_scenes.h"
#include "util/bounded_line.h"
#include "util/temporary_directory_testing.h"

namespace mocap {
namespace {

std::vector<ControlPoint> Observe(const Camera& camera, int count, double noise_px, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::normal_distribution<double> noise(0.0, noise_px);
  std::vector<ControlPoint> points;
  while (static_cast<int>(points.size()) < count) {
    ControlPoint p;
    p.point_in_world = Eigen::Vector3d(800.0 * unit(rng), 800.0 * unit(rng), 900.0 + 700.0 * unit(rng));
    if (!camera.ProjectToPixel(p.point_in_world, &p.pixel) || !camera.InImage(p.pixel)) continue;
    p.pixel += Eigen::Vector2d(noise(rng), noise(rng));
    points.push_back(p);
  }
  return points;
}

DltOptions Options() {
  DltOptions options;
  options.width = 1280;
  options.height = 800;
  return options;
}

TEST(DltTest, RecoversTheCameraFromNoiselessPoints) {
  const Camera truth = testing::LookAtCamera(4, Eigen::Vector3d(3500, -2000, 2500), Eigen::Vector3d(0, 0, 900));
  const std::vector<ControlPoint> points = Observe(truth, 8, 0.0, 1);
  DltOptions options = Options();
  options.refine = false;
  const DltResult result = CalibrateDlt(points, options);
  EXPECT_LT(result.linear_rms_px, 1e-6);
  EXPECT_LT(result.camera_rms_px, 1e-6);
  EXPECT_NEAR(result.camera.intrinsics.fx, truth.intrinsics.fx, 1e-5);
  EXPECT_NEAR(result.camera.intrinsics.cy, truth.intrinsics.cy, 1e-5);
  EXPECT_NEAR(result.skew_px, 0.0, 1e-6);
  EXPECT_LT((result.camera.CenterInWorld() - truth.CenterInWorld()).norm(), 1e-5);
  EXPECT_LT((result.camera.rotation - truth.rotation).norm(), 1e-9);
  for (const ControlPoint& p : points) {
    EXPECT_LT((ProjectDlt(result.parameters, p.point_in_world) - p.pixel).norm(), 1e-6);
  }
}

TEST(DltTest, NoisyPointsGiveNoiseLevelResiduals) {
  const Camera truth = testing::LookAtCamera(4, Eigen::Vector3d(-3000, 2500, 2200), Eigen::Vector3d(0, 0, 900));
  const std::vector<ControlPoint> points = Observe(truth, 40, 0.2, 2);
  const DltResult result = CalibrateDlt(points, Options());
  EXPECT_LT(result.camera_rms_px, 0.35);  // sigma 0.2 per coordinate: 0.28 per observation
  EXPECT_LT(result.camera_rms_px, result.linear_rms_px + 1e-9);
  EXPECT_LT((result.camera.CenterInWorld() - truth.CenterInWorld()).norm(), 20.0);
  EXPECT_NEAR(result.camera.intrinsics.fx / truth.intrinsics.fx, 1.0, 0.01);
}

TEST(DltTest, RefinesLensDistortionWhenAsked) {
  // Close enough that the control points reach the image corners, where distortion shows.
  Camera truth = testing::LookAtCamera(4, Eigen::Vector3d(1500, 1500, 1600), Eigen::Vector3d(0, 0, 900));
  truth.intrinsics.distortion = {-0.2, 0.06, 0.0, 0.0, 0.0};
  const std::vector<ControlPoint> points = Observe(truth, 120, 0.1, 3);
  DltOptions options = Options();
  const DltResult plain = CalibrateDlt(points, options);
  options.refine_distortion = true;
  const DltResult refined = CalibrateDlt(points, options);
  EXPECT_GT(plain.camera_rms_px, 1.0);
  EXPECT_LT(refined.camera_rms_px, 0.18);  // sigma 0.1 per coordinate: 0.14 per observation
  EXPECT_NEAR(refined.camera.intrinsics.distortion[0], -0.2, 0.02);
}

TEST(DltTest, RefusesDegenerateInput) {
  const Camera truth = testing::LookAtCamera(4, Eigen::Vector3d(3000, 0, 2000), Eigen::Vector3d(0, 0, 900));
  std::vector<ControlPoint> points = Observe(truth, 5, 0.0, 4);
  EXPECT_THROW(CalibrateDlt(points, Options()), std::invalid_argument);
  points.clear();
  for (int i = 0; i < 12; ++i) {
    ControlPoint p;
    p.point_in_world = Eigen::Vector3d(100.0 * (i % 4), 150.0 * (i / 4), 0.0);
    truth.ProjectToPixel(p.point_in_world, &p.pixel);
    points.push_back(p);
  }
  EXPECT_THROW(CalibrateDlt(points, Options()), std::invalid_argument);
  EXPECT_THROW(CalibrateDlt(Observe(truth, 10, 0.0, 5), DltOptions()), std::invalid_argument);
}

TEST(DltTest, ReadsControlPointFiles) {
  const testing::TemporaryDirectory temp("dlt_test");
  const std::string path = temp.File("points.txt");
  {
    std::ofstream out(path);
    out << "# x y z u v\n10 20 30 100.5 200.25\n\n  -1 0 5e2 3 4   # comment\n";
  }
  const std::vector<ControlPoint> points = ReadControlPoints(path);
  ASSERT_EQ(points.size(), 2u);
  EXPECT_EQ(points[1].point_in_world, Eigen::Vector3d(-1, 0, 500));
  EXPECT_EQ(points[0].pixel, Eigen::Vector2d(100.5, 200.25));
  {
    std::ofstream out(path);
    out << "1 2 3 4\n";
  }
  EXPECT_THROW(ReadControlPoints(path), std::runtime_error);
  {
    std::ofstream out(path);
    out << "1 2 3 4 x\n";
  }
  EXPECT_THROW(ReadControlPoints(path), std::runtime_error);
  {
    std::ofstream out(path);
    out << "1 2 3 4 5\n" << std::string(kMaxTextLineBytes + 1, '7');
  }
  try {
    ReadControlPoints(path);
    ADD_FAILURE() << "a line without end was read";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(":2: longer than 1 MiB"), std::string::npos) << e.what();
  }
  std::filesystem::remove(path);
  EXPECT_THROW(ReadControlPoints(path), std::runtime_error);
}

}  // namespace
}  // namespace mocap

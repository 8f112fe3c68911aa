// Seed 000's target end to end: the generator's layout rendered through a simulated camera,
// its corners found by Harris detection, and the camera calibrated from them by the DLT within
// 0.5 px reprojection RMS and close to the camera that rendered it.
#include "sim/target_render.h"

#include <cstdio>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "calib/calibration_target.h"
#include "calib/dlt.h"
#include "calib/target_detection.h"
#include "simcore/camera_bump.h"
#include "simcore/look_at.h"

namespace mocap {
namespace {

Camera TargetCamera(const Eigen::Vector3d& centre, std::array<double, 5> distortion) {
  Camera camera;
  camera.id = 1;
  camera.intrinsics.width = 1280;
  camera.intrinsics.height = 800;
  camera.intrinsics.fx = 1100.0;
  camera.intrinsics.fy = 1100.0;
  camera.intrinsics.cx = 652.0;
  camera.intrinsics.cy = 396.0;
  camera.intrinsics.distortion = distortion;
  const CalibrationTargetLayout layout;
  AimCamera(centre, Eigen::Vector3d(0.5 * layout.PageWidthMm(), 20.0, 20.0), Eigen::Vector3d::UnitZ(), &camera);
  return camera;
}

TargetRenderOptions FastRender() {
  TargetRenderOptions options;
  options.supersample = 3;
  return options;
}

struct Case {
  const char* name;
  Eigen::Vector3d centre;
  std::array<double, 5> distortion;
};

TEST(TargetRenderTest, RenderedTargetGivesADltCalibrationWithinHalfAPixel) {
  const CalibrationTargetLayout layout;
  for (const Case& c : {Case{"pinhole, from the front", {180.0, 330.0, 300.0}, {0.0, 0.0, 0.0, 0.0, 0.0}},
                        Case{"barrel lens, from the side", {-120.0, 300.0, 320.0}, {-0.08, 0.03, 0.0005, -0.0004, 0.0}},
                        // Low and from the side: the floor's holed square is so slanted that a
                        // neighbouring corner is nearer its holes in the image than corner 0.
                        Case{"barrel lens, low from the side", {-80.0, 300.0, 240.0}, {-0.05, 0.01, 0.0, 0.0, 0.0}}}) {
    SCOPED_TRACE(c.name);
    const Camera truth = TargetCamera(c.centre, c.distortion);
    const cv::Mat image = RenderTarget(layout, truth, FastRender());
    const TargetDetection detection = DetectTargetPoints(image, layout);
    EXPECT_EQ(detection.wall_points, layout.PointsPerFace());
    EXPECT_EQ(detection.floor_points, layout.PointsPerFace());
    // Every point is where the true camera projects its corner.
    double worst = 0.0, sum = 0.0;
    for (const ControlPoint& point : detection.points) {
      Eigen::Vector2d projected;
      ASSERT_TRUE(truth.ProjectToPixel(point.point_in_world, &projected));
      const double error = (projected - point.pixel).norm();
      worst = std::max(worst, error);
      sum += error * error;
    }
    const double detection_rms = std::sqrt(sum / detection.points.size());
    EXPECT_LT(detection_rms, 0.3);
    EXPECT_LT(worst, 1.0);

    DltOptions options;
    options.width = truth.intrinsics.width;
    options.height = truth.intrinsics.height;
    options.refine_distortion = truth.intrinsics.HasDistortion();
    const DltResult dlt = CalibrateDlt(detection.points, options);
    const PoseChange pose = ComparePoses(dlt.camera, truth);
    std::printf("%s: %zu points, detection RMS %.3f px (worst %.3f), DLT linear RMS %.3f px, camera RMS %.3f px, "
                "centre off by %.2f mm, rotation by %.3f deg, fx by %.2f %%\n",
                c.name, detection.points.size(), detection_rms, worst, dlt.linear_rms_px, dlt.camera_rms_px,
                pose.centre_mm, pose.rotation_deg, 100.0 * (dlt.camera.intrinsics.fx / truth.intrinsics.fx - 1.0));
    EXPECT_LT(dlt.camera_rms_px, 0.5);
    EXPECT_LT(pose.centre_mm, 10.0);
    EXPECT_LT(pose.rotation_deg, 0.5);
  }
}

TEST(TargetRenderTest, MissingFaceOrEmptyImageIsRefusedWithAReason) {
  const CalibrationTargetLayout layout;
  cv::Mat blank(400, 600, CV_8UC1, cv::Scalar(128));
  try {
    DetectTargetPoints(blank, layout);
    FAIL() << "a blank image gave points";
  } catch (const std::runtime_error& error) {
    EXPECT_NE(std::string(error.what()).find("wall face's first square"), std::string::npos) << error.what();
  }
  // Looking at the wall only: the floor's holed square is out of view.
  Camera camera = TargetCamera({95.0, 400.0, 60.0}, {0.0, 0.0, 0.0, 0.0, 0.0});
  AimCamera(camera.CenterInWorld(), Eigen::Vector3d(95.0, 0.0, 120.0), Eigen::Vector3d::UnitZ(), &camera);
  const cv::Mat wall_only = RenderTarget(layout, camera, FastRender());
  EXPECT_THROW(DetectTargetPoints(wall_only, layout), std::runtime_error);
  EXPECT_THROW(DetectTargetPoints(cv::Mat(), layout), std::runtime_error);
  EXPECT_THROW(DetectTargetPoints(cv::Mat(100, 100, CV_8UC3), layout), std::runtime_error);
}

// Images that are not the target (noise, random dark rectangles, some holed) never crash the
// detector: points that name real target indices, or a runtime_error.
TEST(TargetRenderTest, ArbitraryImagesGiveAReasonOrValidPoints) {
  const CalibrationTargetLayout layout;
  cv::RNG rng(7);
  for (int trial = 0; trial < 30; ++trial) {
    cv::Mat image(240 + trial * 7, 320 + trial * 5, CV_8UC1);
    rng.fill(image, cv::RNG::UNIFORM, 0, trial % 3 == 0 ? 255 : 60);
    image += cv::Scalar(trial % 3 == 0 ? 0 : 180);
    for (int r = 0; r < trial; ++r) {
      const cv::Point corner(rng.uniform(0, image.cols), rng.uniform(0, image.rows));
      const cv::Size size(rng.uniform(4, 60), rng.uniform(4, 60));
      cv::rectangle(image, cv::Rect(corner, size), cv::Scalar(20), cv::FILLED);
      if (r % 4 == 0) cv::rectangle(image, cv::Rect(corner + cv::Point(3, 3), cv::Size(3, 3)), cv::Scalar(230), cv::FILLED);
    }
    try {
      const TargetDetection detection = DetectTargetPoints(image, layout);
      for (int index : detection.indices) {
        EXPECT_GE(index, 0);
        EXPECT_LT(index, layout.NumPoints());
      }
    } catch (const std::runtime_error&) {
    }
  }
}

TEST(CalibrationTargetTest, LayoutJsonAndSvgAgree) {
  CalibrationTargetLayout layout;
  layout.rows = 2;
  layout.cols = 3;
  const nlohmann::json document = TargetToJson(layout);
  ASSERT_EQ(document["points"].size(), static_cast<size_t>(layout.NumPoints()));
  const CalibrationTargetLayout back = TargetFromJson(document, "test");
  EXPECT_EQ(back.rows, 2);
  EXPECT_EQ(back.cols, 3);
  // The wall's points stand in y = 0, the floor's lie in z = 0, all corners distinct.
  for (const auto& point : document["points"]) {
    const int axis = point["face"] == "wall" ? 1 : 2;
    EXPECT_EQ(point["xyz"][axis].get<double>(), 0.0);
    EXPECT_EQ(layout.PointInWorld(point["index"]), Eigen::Vector3d(point["xyz"][0], point["xyz"][1], point["xyz"][2]));
  }
  // Ink: a square's inside, not the gap, not the first square's holes.
  const Eigen::Vector2d inside = layout.CornerOnFace(1, 1, 0) + Eigen::Vector2d(1.0, 1.0);
  EXPECT_TRUE(layout.InkAt(TargetFace::kWall, inside));
  EXPECT_FALSE(layout.InkAt(TargetFace::kWall, inside - Eigen::Vector2d(2.0, 0.0)));
  EXPECT_FALSE(layout.InkAt(TargetFace::kWall, layout.HoleCentres(TargetFace::kWall)[0]));
  EXPECT_TRUE(layout.InkAt(TargetFace::kWall, layout.HoleCentres(TargetFace::kFloor)[1]));
  const std::string svg = TargetSvg(layout);
  size_t rects = 0;
  for (size_t at = svg.find("fill=\"black\""); at != std::string::npos; at = svg.find("fill=\"black\"", at + 1)) ++rects;
  EXPECT_EQ(rects, 2u * 2u * 3u);
  // Damaged documents: a clear error, never a layout that fails Check().
  nlohmann::json bad = document;
  bad["layout"]["rows"] = 1;
  EXPECT_THROW(TargetFromJson(bad, "test"), std::runtime_error);
  bad = document;
  bad["layout"]["square_mm"] = "20";
  EXPECT_THROW(TargetFromJson(bad, "test"), std::runtime_error);
  bad = document;
  bad["type"] = "checkerboard";
  EXPECT_THROW(TargetFromJson(bad, "test"), std::runtime_error);
  EXPECT_THROW(TargetFromJson(nlohmann::json::array(), "test"), std::runtime_error);
}

}  // namespace
}  // namespace mocap

// Intrinsics from synthetic images: checkerboard and ChArUco boards rendered exactly through a
// known camera with lens distortion (inverse mapping of every pixel onto the board plane), then
// calibrated; plus refusal when the board is missing.
#include "calib/intrinsics.h"

#include <cmath>
#include <stdexcept>

#include <opencv2/aruco/charuco.hpp>
#include <opencv2/imgproc.hpp>
#include <Eigen/Geometry>
#include <gtest/gtest.h>

namespace mocap {
namespace {

constexpr double kPixelsPerMm = 8.0;
constexpr double kMarginMm = 20.0;

Camera TrueCamera() {
  Camera camera;
  camera.intrinsics.width = 1024;
  camera.intrinsics.height = 768;
  camera.intrinsics.fx = 820.0;
  camera.intrinsics.fy = 818.0;
  camera.intrinsics.cx = 520.0;
  camera.intrinsics.cy = 380.0;
  camera.intrinsics.distortion = {-0.22, 0.07, 0.0006, -0.0004, 0.0};
  return camera;
}

// Board texture: white margin, squares_x x squares_y squares, top-left square black.
cv::Mat CheckerboardTexture(const CalibrationTarget& target) {
  const int width = static_cast<int>(std::lround((target.squares_x * target.square_mm + 2 * kMarginMm) * kPixelsPerMm));
  const int height =
      static_cast<int>(std::lround((target.squares_y * target.square_mm + 2 * kMarginMm) * kPixelsPerMm));
  cv::Mat texture(height, width, CV_8U, cv::Scalar(255));
  const int square = static_cast<int>(std::lround(target.square_mm * kPixelsPerMm));
  const int margin = static_cast<int>(std::lround(kMarginMm * kPixelsPerMm));
  for (int y = 0; y < target.squares_y; ++y) {
    for (int x = 0; x < target.squares_x; ++x) {
      if ((x + y) % 2 == 0) {
        cv::rectangle(texture, cv::Rect(margin + x * square, margin + y * square, square, square), cv::Scalar(0),
                      cv::FILLED);
      }
    }
  }
  return texture;
}

cv::Mat CharucoTexture(const CalibrationTarget& target) {
  const cv::Ptr<cv::aruco::Dictionary> dictionary = cv::aruco::getPredefinedDictionary(cv::aruco::DICT_4X4_50);
  const cv::Ptr<cv::aruco::CharucoBoard> board =
      cv::aruco::CharucoBoard::create(target.squares_x, target.squares_y, static_cast<float>(target.square_mm),
                                      static_cast<float>(target.marker_mm), dictionary);
  const int margin = static_cast<int>(std::lround(kMarginMm * kPixelsPerMm));
  const cv::Size size(static_cast<int>(std::lround(target.squares_x * target.square_mm * kPixelsPerMm)) + 2 * margin,
                      static_cast<int>(std::lround(target.squares_y * target.square_mm * kPixelsPerMm)) + 2 * margin);
  cv::Mat texture;
  board->draw(size, texture, margin, 1);
  return texture;
}

// cam_from_board looking at `aim` (board mm, z = 0) from `eye`; image up is board -y.
Camera PosedCamera(const Eigen::Vector3d& eye, const Eigen::Vector3d& aim) {
  Camera camera = TrueCamera();
  const Eigen::Vector3d forward = (aim - eye).normalized();
  const Eigen::Vector3d right = Eigen::Vector3d::UnitY().cross(forward).normalized();
  const Eigen::Vector3d down = forward.cross(right);
  camera.rotation.row(0) = right;
  camera.rotation.row(1) = down;
  camera.rotation.row(2) = forward;
  camera.translation = -camera.rotation * eye;
  return camera;
}

// Every image pixel traced back through the lens onto the board plane and sampled there.
cv::Mat Render(const Camera& camera, const cv::Mat& texture) {
  const int width = camera.intrinsics.width, height = camera.intrinsics.height;
  cv::Mat map_x(height, width, CV_32F), map_y(height, width, CV_32F);
  const Eigen::Vector3d centre = camera.CenterInWorld();
  for (int v = 0; v < height; ++v) {
    for (int u = 0; u < width; ++u) {
      const Eigen::Vector3d ray = camera.RayDirectionInWorld(Eigen::Vector2d(u, v));
      float x = -1.0f, y = -1.0f;
      if (ray.z() * centre.z() < 0.0) {
        const Eigen::Vector3d hit = centre - (centre.z() / ray.z()) * ray;
        x = static_cast<float>((hit.x() + kMarginMm) * kPixelsPerMm);
        y = static_cast<float>((hit.y() + kMarginMm) * kPixelsPerMm);
      }
      map_x.at<float>(v, u) = x;
      map_y.at<float>(v, u) = y;
    }
  }
  cv::Mat image;
  cv::remap(texture, image, map_x, map_y, cv::INTER_AREA, cv::BORDER_CONSTANT, cv::Scalar(128));
  cv::GaussianBlur(image, image, cv::Size(0, 0), 0.8);
  return image;
}

std::vector<cv::Mat> RenderViews(const CalibrationTarget& target, const cv::Mat& texture) {
  const Eigen::Vector3d middle(0.5 * target.squares_x * target.square_mm, 0.5 * target.squares_y * target.square_mm, 0);
  std::vector<cv::Mat> images;
  const double offsets[][2] = {{0, 0}, {-1, -1}, {1, -1}, {-1, 1}, {1, 1}, {0, -1}, {0, 1}, {-1, 0}, {1, 0}};
  for (size_t i = 0; i < sizeof(offsets) / sizeof(offsets[0]); ++i) {
    // Tilted views from around the board; the aim point shifts the board towards the image edges.
    const double tilt = 0.45 + 0.05 * static_cast<double>(i % 3);
    const double heading = 0.7 * static_cast<double>(i);
    const Eigen::Vector3d eye =
        middle + 480.0 * Eigen::Vector3d(std::sin(tilt) * std::cos(heading), std::sin(tilt) * std::sin(heading),
                                         -std::cos(tilt));
    const Eigen::Vector3d aim = middle - Eigen::Vector3d(offsets[i][0] * 90.0, offsets[i][1] * 60.0, 0.0);
    images.push_back(Render(PosedCamera(eye, aim), texture));
  }
  return images;
}

void ExpectCloseToTruth(const IntrinsicsResult& result, double max_rms_px) {
  const CameraIntrinsics truth = TrueCamera().intrinsics;
  EXPECT_LT(result.rms_px, max_rms_px);
  EXPECT_NEAR(result.intrinsics.fx / truth.fx, 1.0, 0.01);
  EXPECT_NEAR(result.intrinsics.fy / truth.fy, 1.0, 0.01);
  EXPECT_NEAR(result.intrinsics.cx, truth.cx, 6.0);
  EXPECT_NEAR(result.intrinsics.cy, truth.cy, 6.0);
  EXPECT_NEAR(result.intrinsics.distortion[0], truth.distortion[0], 0.03);
  EXPECT_EQ(result.intrinsics.width, truth.width);
}

TEST(IntrinsicsTest, CheckerboardImagesGiveTheTrueCamera) {
  CalibrationTarget target;
  target.squares_x = 9;
  target.squares_y = 7;
  target.square_mm = 30.0;
  const std::vector<cv::Mat> images = RenderViews(target, CheckerboardTexture(target));
  std::vector<std::string> names;
  for (size_t i = 0; i < images.size(); ++i) names.push_back("view" + std::to_string(i));
  const IntrinsicsResult result = CalibrateIntrinsics(images, names, target, IntrinsicsOptions());
  int used = 0;
  for (const auto& view : result.views) used += view.used ? 1 : 0;
  EXPECT_GE(used, 7);
  ExpectCloseToTruth(result, 0.3);
}

TEST(IntrinsicsTest, CharucoImagesGiveTheTrueCamera) {
  CalibrationTarget target;
  target.type = TargetType::kCharuco;
  target.squares_x = 9;
  target.squares_y = 7;
  target.square_mm = 30.0;
  target.marker_mm = 22.0;
  const std::vector<cv::Mat> images = RenderViews(target, CharucoTexture(target));
  std::vector<std::string> names(images.size(), "charuco");
  const IntrinsicsResult result = CalibrateIntrinsics(images, names, target, IntrinsicsOptions());
  // ChArUco corners are located through the markers' homographies, a little less sharply.
  ExpectCloseToTruth(result, 0.5);
}

TEST(IntrinsicsTest, ImagesWithoutTheBoardAreRefused) {
  std::vector<cv::Mat> images(5, cv::Mat(480, 640, CV_8U, cv::Scalar(90)));
  std::vector<std::string> names(5, "blank");
  try {
    CalibrateIntrinsics(images, names, CalibrationTarget(), IntrinsicsOptions());
    FAIL() << "expected a refusal";
  } catch (const std::runtime_error& error) {
    EXPECT_NE(std::string(error.what()).find("found in 0 of 5"), std::string::npos) << error.what();
  }
  CalibrationTarget bad;
  bad.type = TargetType::kCharuco;
  bad.dictionary = "7x7_9";
  EXPECT_THROW(CalibrateIntrinsics(images, names, bad, IntrinsicsOptions()), std::invalid_argument);
  EXPECT_THROW(TargetTypeFromName("circles"), std::invalid_argument);
}

}  // namespace
}  // namespace mocap

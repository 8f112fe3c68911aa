// Ray tracing of the folded target page.
#include "sim/target_render.h"

#include <cmath>
#include <stdexcept>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

namespace mocap {

void TargetRenderOptions::Check() const {
  if (supersample < 1 || supersample > 16) throw std::invalid_argument("supersample must be within [1, 16]");
  if (!(blur_sigma_px >= 0.0 && blur_sigma_px <= 20.0)) throw std::invalid_argument("blur_sigma_px must be within [0, 20]");
  if (!(noise >= 0.0 && noise <= 100.0)) throw std::invalid_argument("noise must be within [0, 100]");
  for (double level : {ink, paper, background}) {
    if (!(level >= 0.0 && level <= 255.0)) throw std::invalid_argument("grey levels must be within [0, 255]");
  }
}

namespace {

// Grey level where the ray from `centre` along `direction` first meets the page.
double Shade(const CalibrationTargetLayout& layout, const Eigen::Vector3d& centre, const Eigen::Vector3d& direction,
             const TargetRenderOptions& options) {
  const double width = layout.PageWidthMm(), half = layout.HalfHeightMm();
  double nearest = 1e300;
  double level = options.background;
  // Wall: y = 0, (u, v) = (x, z); floor: z = 0, (u, v) = (x, y).
  for (const TargetFace face : {TargetFace::kWall, TargetFace::kFloor}) {
    const int axis = face == TargetFace::kWall ? 1 : 2;
    if (std::abs(direction[axis]) < 1e-12) continue;
    const double t = -centre[axis] / direction[axis];
    if (!(t > 0.0) || t >= nearest) continue;
    const Eigen::Vector3d p = centre + t * direction;
    const Eigen::Vector2d uv(p.x(), face == TargetFace::kWall ? p.z() : p.y());
    if (uv.x() < 0.0 || uv.x() > width || uv.y() < 0.0 || uv.y() > half) continue;
    nearest = t;
    level = layout.InkAt(face, uv) ? options.ink : options.paper;
  }
  return level;
}

}  // namespace

cv::Mat RenderTarget(const CalibrationTargetLayout& layout, const Camera& camera, const TargetRenderOptions& options) {
  layout.Check();
  options.Check();
  const int width = camera.intrinsics.width, height = camera.intrinsics.height;
  if (width < 16 || height < 16 || width > 8192 || height > 8192)
    throw std::invalid_argument("camera image size must be within 16..8192 px");
  const Eigen::Vector3d centre = camera.CenterInWorld();
  const Eigen::Matrix3d world_from_cam = camera.rotation.transpose();
  cv::Mat image(height, width, CV_32F);
  const int n = options.supersample;
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      double sum = 0.0;
      for (int sy = 0; sy < n; ++sy) {
        for (int sx = 0; sx < n; ++sx) {
          // Pixel centres at integer coordinates (OpenCV), samples spread over the pixel's area.
          const Eigen::Vector2d pixel(x - 0.5 + (sx + 0.5) / n, y - 0.5 + (sy + 0.5) / n);
          const Eigen::Vector2d normalized = camera.UndistortPixel(pixel);
          const Eigen::Vector3d direction = world_from_cam * Eigen::Vector3d(normalized.x(), normalized.y(), 1.0);
          sum += Shade(layout, centre, direction, options);
        }
      }
      image.at<float>(y, x) = static_cast<float>(sum / (n * n));
    }
  }
  if (options.blur_sigma_px > 0.0) cv::GaussianBlur(image, image, cv::Size(0, 0), options.blur_sigma_px);
  if (options.noise > 0.0) {
    cv::Mat noise(height, width, CV_32F);
    cv::RNG rng(options.seed);
    rng.fill(noise, cv::RNG::NORMAL, 0.0, options.noise);
    image += noise;
  }
  cv::Mat out;
  image.convertTo(out, CV_8U);  // rounds and saturates
  return out;
}

}  // namespace mocap

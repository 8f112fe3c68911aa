// Seed 000's square target (calib/calibration_target.h) as one camera of the simulator sees it:
// every pixel's samples are traced through the camera model (lens distortion included) onto the
// folded page, then blurred like a lens and given sensor noise. What target detection and
// `calibrate dlt` are tested on, and what `sim target-image` writes.
// Pure function; options Check() throws std::invalid_argument.
#pragma once

#include <cstdint>

#include <opencv2/core/mat.hpp>

#include "calib/calibration_target.h"
#include "geometry/camera.h"

namespace mocap {

struct TargetRenderOptions {
  int supersample = 4;         // samples per pixel along each axis
  double blur_sigma_px = 0.7;  // Gaussian lens blur
  double noise = 2.0;          // sensor noise sigma, grey levels
  double ink = 35.0;           // grey levels of the printed squares,
  double paper = 215.0;        // of the paper
  double background = 110.0;   // and of the room behind the target
  uint64_t seed = 1;

  void Check() const;
};

// 8-bit grey image of the camera's size.
cv::Mat RenderTarget(const CalibrationTargetLayout& layout, const Camera& camera, const TargetRenderOptions& options);

}  // namespace mocap

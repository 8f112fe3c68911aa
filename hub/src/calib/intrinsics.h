// `calibrate intrinsics`: a camera's focal lengths, principal point and lens distortion from
// images of a planar target (checkerboard, or ChArUco when only part of the board is in view),
// by OpenCV's corner detectors and calibrateCamera.
#pragma once

#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "geometry/camera.h"

namespace mocap {

enum class TargetType { kCheckerboard, kCharuco };
const char* TargetTypeName(TargetType type);
// Throws std::invalid_argument listing the valid names.
TargetType TargetTypeFromName(const std::string& name);

struct CalibrationTarget {
  TargetType type = TargetType::kCheckerboard;
  // Squares across and down (a checkerboard of 10 x 7 squares has 9 x 6 inner corners).
  int squares_x = 10;
  int squares_y = 7;
  double square_mm = 30.0;
  double marker_mm = 22.0;            // ChArUco only: side of the ArUco markers
  std::string dictionary = "4x4_50";  // ChArUco only: 4x4_50, 5x5_100, 6x6_250, ...

  void Check() const;
  // The board corners in its own plane (z = 0), mm; index = OpenCV's corner id.
  std::vector<cv::Point3f> Corners() const;
};

struct IntrinsicsOptions {
  int min_views = 4;          // images in which the target must be found
  int min_corners = 8;        // corners a ChArUco view needs
  bool fix_k3 = true;         // k3 is rarely determined by a handful of views
  bool fix_tangential = false;

  void Check() const;
};

struct IntrinsicsView {
  std::string name;
  bool used = false;
  std::string reason;  // why the view was not used
  int corners = 0;
};

struct IntrinsicsResult {
  CameraIntrinsics intrinsics;
  double rms_px = 0.0;  // OpenCV's RMS reprojection error
  std::vector<IntrinsicsView> views;
};

// Finds the target in every image (8-bit grey or BGR) and calibrates. Throws std::runtime_error
// with advice when fewer than min_views images show the target.
IntrinsicsResult CalibrateIntrinsics(const std::vector<cv::Mat>& images, const std::vector<std::string>& names,
                                     const CalibrationTarget& target, const IntrinsicsOptions& options);

// Image files of a list of files and directories (directories: every .png .jpg .jpeg .bmp
// .pgm .tif file, sorted). Throws std::runtime_error for a file that cannot be read.
std::vector<std::string> ExpandImagePaths(const std::vector<std::string>& paths);

// The files as 8-bit grey images. Throws std::runtime_error naming a file that is no image.
std::vector<cv::Mat> ReadGreyImages(const std::vector<std::string>& files);

}  // namespace mocap

// Seed 000's camera blocks: Reg Willson's Tsai calibration as 19 numbers, one per line (Ncx Nfx
// dx dy dpx dpy Cx Cy sx f kappa1 Tx Ty Tz Rx Ry Rz p1 p2), and their conversion to the OpenCV
// model of the calibration JSON. Tsai's single radial term maps distorted to undistorted sensor
// coordinates (Xu = Xd (1 + kappa1 r_d^2)), the inverse direction of OpenCV's, so k1 k2 k3 are
// fitted to it over the image and the fit error is reported.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "geometry/camera.h"

namespace mocap {

// The widest frame buffer (Nfx) taken: the calibration file's limit on image sizes.
inline constexpr double kMaxTsaiImageWidth = 1 << 20;

struct TsaiCamera {
  double ncx = 0, nfx = 0, dx = 0, dy = 0, dpx = 0, dpy = 0;  // sensor and frame buffer
  double cx = 0, cy = 0, sx = 1;                               // image centre (px), x scale
  double f = 0, kappa1 = 0;                                    // focal length (mm), radial term
  double tx = 0, ty = 0, tz = 0;                               // cam_from_world translation (mm)
  double rx = 0, ry = 0, rz = 0;                               // rotation angles (rad)
  double p1 = 0, p2 = 0;                                       // unused by the Tsai model

  // cam_from_world rotation: Rz * Ry * Rx (Willson's convention).
  Eigen::Matrix3d Rotation() const;
  // Sets rx ry rz from a cam_from_world rotation matrix.
  void SetRotation(const Eigen::Matrix3d& rotation);
  // Exact Tsai projection to frame-buffer pixels; false behind the camera.
  bool Project(const Eigen::Vector3d& point_in_world, Eigen::Vector2d* pixel) const;
  // Throws std::invalid_argument naming the bad value.
  void Check() const;
};

// 19 numbers, each optionally followed by a "//" comment. `source` names the origin in errors;
// throws std::runtime_error on anything else.
TsaiCamera ParseTsaiBlock(const std::vector<std::string>& lines, const std::string& source);

// Every block of a file, blocks separated by blank lines.
std::vector<TsaiCamera> ReadTsaiFile(const std::string& path);

struct TsaiConversion {
  Camera camera;
  double max_error_px = 0.0;  // worst difference between the Tsai and OpenCV projections over the image
};

// width/height: image size (Tsai blocks carry only the width, Nfx); height 0 takes 3/4 of it.
// Throws std::invalid_argument for a camera that fails Check(), a lens OpenCV's terms cannot fit,
// or a result the calibration file cannot hold (io/calibration_json.h).
TsaiConversion CameraFromTsai(const TsaiCamera& tsai, uint32_t id, int width, int height);

}  // namespace mocap

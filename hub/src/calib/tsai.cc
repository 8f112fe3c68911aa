// Tsai model: world -> camera (R, T) -> undistorted sensor (f) -> distorted sensor (inverse of
// Xu = Xd (1 + kappa1 r_d^2), by Newton on the radius) -> frame buffer (sx, dpx, dpy, Cx, Cy).
#include "calib/tsai.h"

#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include "io/calibration_json.h"
#include "util/bounded_line.h"

namespace mocap {
namespace {

// Distorted sensor radius rd for an undistorted radius ru: ru = rd (1 + k rd^2).
double DistortedRadius(double ru, double kappa1) {
  double rd = ru;
  for (int i = 0; i < 30; ++i) {
    const double value = rd * (1.0 + kappa1 * rd * rd) - ru;
    const double slope = 1.0 + 3.0 * kappa1 * rd * rd;
    if (slope <= 0.0) break;
    const double step = value / slope;
    rd -= step;
    if (std::abs(step) < 1e-15 * (1.0 + ru)) break;
  }
  return rd;
}

}  // namespace

Eigen::Matrix3d TsaiCamera::Rotation() const {
  return (Eigen::AngleAxisd(rz, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(ry, Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(rx, Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

void TsaiCamera::SetRotation(const Eigen::Matrix3d& rotation) {
  const Eigen::Vector3d angles = rotation.eulerAngles(2, 1, 0);  // R = Rz Ry Rx
  rz = angles(0);
  ry = angles(1);
  rx = angles(2);
}

bool TsaiCamera::Project(const Eigen::Vector3d& point_in_world, Eigen::Vector2d* pixel) const {
  const Eigen::Vector3d in_cam = Rotation() * point_in_world + Eigen::Vector3d(tx, ty, tz);
  if (!(in_cam.z() > 1e-9)) return false;
  const Eigen::Vector2d undistorted = f * in_cam.head<2>() / in_cam.z();
  const double ru = undistorted.norm();
  const Eigen::Vector2d distorted = ru > 0.0 ? undistorted * (DistortedRadius(ru, kappa1) / ru) : undistorted;
  *pixel = Eigen::Vector2d(sx * distorted.x() / dpx + cx, distorted.y() / dpy + cy);
  return true;
}

void TsaiCamera::Check() const {
  if (!(dpx > 0.0 && dpy > 0.0)) throw std::invalid_argument("dpx and dpy must be > 0");
  if (!(f > 0.0)) throw std::invalid_argument("f must be > 0");
  if (!(sx > 0.0)) throw std::invalid_argument("sx must be > 0");
  // Nfx is the image width the conversion takes by default: a pixel count the calibration file
  // can hold (0.2 became a camera 0 px wide, a file the calibration reader refuses).
  if (!(nfx >= 0.5 && nfx <= kMaxTsaiImageWidth))
    throw std::invalid_argument("Nfx must be an image width from 1 to " + std::to_string(kMaxTsaiImageWidth) + " px");
  for (double v : {ncx, nfx, dx, dy, dpx, dpy, cx, cy, sx, f, kappa1, tx, ty, tz, rx, ry, rz, p1, p2}) {
    if (!std::isfinite(v)) throw std::invalid_argument("values must be finite");
  }
  if (!std::isfinite(sx * f / dpx) || !std::isfinite(f / dpy))
    throw std::invalid_argument("the focal length in pixels (sx f / dpx, f / dpy) must be finite");
}

TsaiCamera ParseTsaiBlock(const std::vector<std::string>& lines, const std::string& source) {
  if (lines.size() != 19) {
    throw std::runtime_error(source + ": a Tsai camera block has 19 values, found " + std::to_string(lines.size()));
  }
  double values[19];
  for (size_t i = 0; i < 19; ++i) {
    std::string text = lines[i];
    const size_t comment = text.find("//");
    if (comment != std::string::npos) text.resize(comment);
    std::istringstream in(text);
    std::string extra;
    if (!(in >> values[i]) || (in >> extra) || !std::isfinite(values[i])) {
      throw std::runtime_error(source + ": value " + std::to_string(i + 1) + " of the Tsai block is not a number: '" +
                               lines[i] + "'");
    }
  }
  TsaiCamera t;
  t.ncx = values[0]; t.nfx = values[1]; t.dx = values[2]; t.dy = values[3]; t.dpx = values[4]; t.dpy = values[5];
  t.cx = values[6]; t.cy = values[7]; t.sx = values[8]; t.f = values[9]; t.kappa1 = values[10];
  t.tx = values[11]; t.ty = values[12]; t.tz = values[13];
  t.rx = values[14]; t.ry = values[15]; t.rz = values[16]; t.p1 = values[17]; t.p2 = values[18];
  try {
    t.Check();
  } catch (const std::invalid_argument& error) {
    throw std::runtime_error(source + ": Tsai block: " + error.what());
  }
  return t;
}

std::vector<TsaiCamera> ReadTsaiFile(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path + ": cannot open");
  std::vector<TsaiCamera> cameras;
  std::vector<std::string> block;
  std::string line;
  int number = 0, block_start = 0;
  auto flush = [&]() {
    if (block.empty()) return;
    cameras.push_back(ParseTsaiBlock(block, path + ":" + std::to_string(block_start)));
    block.clear();
  };
  for (LineRead read; (read = ReadBoundedLine(in, &line, kMaxTextLineBytes)) != LineRead::kEnd;) {
    ++number;
    if (read == LineRead::kTooLong)
      throw std::runtime_error(path + ":" + std::to_string(number) + ": longer than 1 MiB: not a Tsai file");
    if (line.find_first_not_of(" \t\r") == std::string::npos) {
      flush();
      continue;
    }
    if (block.empty()) block_start = number;
    block.push_back(line);
  }
  flush();
  if (cameras.empty()) throw std::runtime_error(path + ": no Tsai camera block");
  return cameras;
}

TsaiConversion CameraFromTsai(const TsaiCamera& tsai, uint32_t id, int width, int height) {
  tsai.Check();
  if (width <= 0) width = static_cast<int>(std::lround(tsai.nfx));
  if (height <= 0) height = width * 3 / 4;
  TsaiConversion out;
  Camera& camera = out.camera;
  camera.id = id;
  camera.intrinsics.width = width;
  camera.intrinsics.height = height;
  camera.intrinsics.fx = tsai.sx * tsai.f / tsai.dpx;
  camera.intrinsics.fy = tsai.f / tsai.dpy;
  camera.intrinsics.cx = tsai.cx;
  camera.intrinsics.cy = tsai.cy;
  camera.rotation = tsai.Rotation();
  camera.translation = Eigen::Vector3d(tsai.tx, tsai.ty, tsai.tz);

  // Sample the image, map each pixel to Tsai's undistorted normalized coordinates exactly, and
  // fit OpenCV's x_d = x_u (1 + k1 r^2 + k2 r^4 + k3 r^6) by linear least squares.
  const int grid = 24;
  std::vector<Eigen::Vector2d> undistorted, distorted, pixels;
  for (int i = 0; i <= grid; ++i) {
    for (int j = 0; j <= grid; ++j) {
      const Eigen::Vector2d pixel(width * static_cast<double>(i) / grid, height * static_cast<double>(j) / grid);
      const Eigen::Vector2d sensor(tsai.dpx * (pixel.x() - tsai.cx) / tsai.sx, tsai.dpy * (pixel.y() - tsai.cy));
      const double factor = 1.0 + tsai.kappa1 * sensor.squaredNorm();
      if (!(factor > 0.0)) continue;  // beyond where the Tsai model is invertible
      pixels.push_back(pixel);
      distorted.push_back(sensor / tsai.f);
      undistorted.push_back(sensor * factor / tsai.f);
    }
  }
  Eigen::MatrixXd design(2 * undistorted.size(), 3);
  Eigen::VectorXd target(2 * undistorted.size());
  for (size_t i = 0; i < undistorted.size(); ++i) {
    const double r2 = undistorted[i].squaredNorm();
    for (int a = 0; a < 2; ++a) {
      design.row(2 * i + a) << undistorted[i](a) * r2, undistorted[i](a) * r2 * r2, undistorted[i](a) * r2 * r2 * r2;
      target(2 * i + a) = distorted[i](a) - undistorted[i](a);
    }
  }
  const Eigen::Vector3d k = design.colPivHouseholderQr().solve(target);
  if (!k.allFinite())
    throw std::invalid_argument("Tsai lens (kappa1 " + std::to_string(tsai.kappa1) +
                                ") cannot be fitted by OpenCV's k1 k2 k3 over the image");
  camera.intrinsics.distortion = {k(0), k(1), 0.0, 0.0, k(2)};
  for (size_t i = 0; i < undistorted.size(); ++i) {
    const Eigen::Vector2d opencv = camera.NormalizedToPixel(camera.DistortNormalized(undistorted[i]));
    out.max_error_px = std::max(out.max_error_px, (opencv - pixels[i]).norm());
  }
  // What the import writes must load: a camera the calibration file's reader refuses (a lens
  // whose fitted terms are beyond any real one, an image too wide) is refused here, by its rule.
  try {
    Rig rig;
    rig.cameras.push_back(camera);
    RigFromJson(RigToJson(rig), "Tsai camera");
  } catch (const std::runtime_error& e) {
    throw std::invalid_argument(e.what());
  }
  return out;
}

}  // namespace mocap

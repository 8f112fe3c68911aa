// Target detection per image (findChessboardCorners + cornerSubPix, or ArUco markers +
// interpolated ChArUco corners), then cv::calibrateCamera with the OpenCV 5-term lens model.
#include "calib/intrinsics.h"

#include <algorithm>
#include <filesystem>
#include <map>
#include <stdexcept>

#include <opencv2/aruco/charuco.hpp>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

namespace mocap {
namespace {

const std::map<std::string, int>& Dictionaries() {
  static const std::map<std::string, int> names = {
      {"4x4_50", cv::aruco::DICT_4X4_50},   {"4x4_100", cv::aruco::DICT_4X4_100},
      {"4x4_250", cv::aruco::DICT_4X4_250}, {"5x5_50", cv::aruco::DICT_5X5_50},
      {"5x5_100", cv::aruco::DICT_5X5_100}, {"5x5_250", cv::aruco::DICT_5X5_250},
      {"6x6_50", cv::aruco::DICT_6X6_50},   {"6x6_250", cv::aruco::DICT_6X6_250},
  };
  return names;
}

cv::Mat Grey(const cv::Mat& image) {
  if (image.channels() == 1) return image;
  cv::Mat grey;
  cv::cvtColor(image, grey, image.channels() == 4 ? cv::COLOR_BGRA2GRAY : cv::COLOR_BGR2GRAY);
  return grey;
}

}  // namespace

const char* TargetTypeName(TargetType type) {
  return type == TargetType::kCheckerboard ? "checkerboard" : "charuco";
}

TargetType TargetTypeFromName(const std::string& name) {
  if (name == "checkerboard") return TargetType::kCheckerboard;
  if (name == "charuco") return TargetType::kCharuco;
  throw std::invalid_argument("unknown target '" + name + "' (checkerboard, charuco)");
}

void CalibrationTarget::Check() const {
  if (squares_x < 3 || squares_y < 3 || squares_x > 100 || squares_y > 100) {
    throw std::invalid_argument("the target needs 3..100 squares in each direction");
  }
  if (!(square_mm > 0.0)) throw std::invalid_argument("the square size must be > 0 mm");
  if (type == TargetType::kCharuco) {
    if (!(marker_mm > 0.0 && marker_mm < square_mm)) {
      throw std::invalid_argument("ChArUco markers must be smaller than the squares");
    }
    if (Dictionaries().count(dictionary) == 0) {
      std::string known;
      for (const auto& [name, id] : Dictionaries()) known += (known.empty() ? "" : ", ") + name;
      throw std::invalid_argument("unknown ArUco dictionary '" + dictionary + "' (" + known + ")");
    }
  }
}

std::vector<cv::Point3f> CalibrationTarget::Corners() const {
  std::vector<cv::Point3f> corners;
  for (int y = 1; y < squares_y; ++y) {
    for (int x = 1; x < squares_x; ++x) {
      corners.emplace_back(static_cast<float>(x * square_mm), static_cast<float>(y * square_mm), 0.0f);
    }
  }
  return corners;
}

void IntrinsicsOptions::Check() const {
  if (min_views < 3) throw std::invalid_argument("min_views must be >= 3");
  if (min_corners < 6) throw std::invalid_argument("min_corners must be >= 6");
}

IntrinsicsResult CalibrateIntrinsics(const std::vector<cv::Mat>& images, const std::vector<std::string>& names,
                                     const CalibrationTarget& target, const IntrinsicsOptions& options) {
  target.Check();
  options.Check();
  if (images.size() != names.size()) throw std::invalid_argument("one name per image is needed");
  const std::vector<cv::Point3f> board_corners = target.Corners();
  const cv::Size pattern(target.squares_x - 1, target.squares_y - 1);
  cv::Ptr<cv::aruco::Dictionary> dictionary;
  cv::Ptr<cv::aruco::CharucoBoard> board;
  if (target.type == TargetType::kCharuco) {
    dictionary = cv::aruco::getPredefinedDictionary(Dictionaries().at(target.dictionary));
    board = cv::aruco::CharucoBoard::create(target.squares_x, target.squares_y, static_cast<float>(target.square_mm),
                                            static_cast<float>(target.marker_mm), dictionary);
  }

  IntrinsicsResult result;
  std::vector<std::vector<cv::Point3f>> object_points;
  std::vector<std::vector<cv::Point2f>> image_points;
  cv::Size size;
  for (size_t i = 0; i < images.size(); ++i) {
    IntrinsicsView view;
    view.name = names[i];
    const cv::Mat grey = Grey(images[i]);
    if (grey.empty() || grey.depth() != CV_8U) {
      view.reason = "not an 8-bit image";
      result.views.push_back(view);
      continue;
    }
    if (size.area() == 0) size = grey.size();
    if (grey.size() != size) {
      view.reason = "image size differs from the first image";
      result.views.push_back(view);
      continue;
    }
    std::vector<cv::Point2f> corners;
    std::vector<cv::Point3f> objects;
    if (target.type == TargetType::kCheckerboard) {
      if (!cv::findChessboardCorners(grey, pattern, corners,
                                     cv::CALIB_CB_ADAPTIVE_THRESH | cv::CALIB_CB_NORMALIZE_IMAGE)) {
        view.reason = "checkerboard not found (all inner corners must be visible)";
        result.views.push_back(view);
        continue;
      }
      cv::cornerSubPix(grey, corners, cv::Size(5, 5), cv::Size(-1, -1),
                       cv::TermCriteria(cv::TermCriteria::EPS + cv::TermCriteria::COUNT, 50, 1e-3));
      objects = board_corners;
    } else {
      std::vector<std::vector<cv::Point2f>> marker_corners;
      std::vector<int> marker_ids, corner_ids;
      cv::aruco::detectMarkers(grey, dictionary, marker_corners, marker_ids);
      if (!marker_ids.empty()) {
        cv::aruco::interpolateCornersCharuco(marker_corners, marker_ids, grey, board, corners, corner_ids);
      }
      if (static_cast<int>(corners.size()) < options.min_corners) {
        view.reason = "only " + std::to_string(corners.size()) + " ChArUco corners found (need " +
                      std::to_string(options.min_corners) + ")";
        result.views.push_back(view);
        continue;
      }
      for (int id : corner_ids) objects.push_back(board->chessboardCorners[static_cast<size_t>(id)]);
    }
    view.used = true;
    view.corners = static_cast<int>(corners.size());
    result.views.push_back(view);
    object_points.push_back(objects);
    image_points.push_back(corners);
  }
  if (static_cast<int>(object_points.size()) < options.min_views) {
    throw std::runtime_error("the target was found in " + std::to_string(object_points.size()) + " of " +
                             std::to_string(images.size()) + " images (need " + std::to_string(options.min_views) +
                             "): check the board size options and take more images, tilted and covering the corners "
                             "of the view");
  }
  int flags = 0;
  if (options.fix_k3) flags |= cv::CALIB_FIX_K3;
  if (options.fix_tangential) flags |= cv::CALIB_ZERO_TANGENT_DIST;
  cv::Mat camera_matrix, distortion;
  std::vector<cv::Mat> rvecs, tvecs;
  result.rms_px =
      cv::calibrateCamera(object_points, image_points, size, camera_matrix, distortion, rvecs, tvecs, flags);
  CameraIntrinsics& in = result.intrinsics;
  in.width = size.width;
  in.height = size.height;
  in.fx = camera_matrix.at<double>(0, 0);
  in.fy = camera_matrix.at<double>(1, 1);
  in.cx = camera_matrix.at<double>(0, 2);
  in.cy = camera_matrix.at<double>(1, 2);
  for (int i = 0; i < 5 && i < static_cast<int>(distortion.total()); ++i) {
    in.distortion[static_cast<size_t>(i)] = distortion.at<double>(i);
  }
  return result;
}

std::vector<std::string> ExpandImagePaths(const std::vector<std::string>& paths) {
  static const std::vector<std::string> extensions = {".png", ".jpg", ".jpeg", ".bmp", ".pgm", ".tif", ".tiff"};
  std::vector<std::string> files;
  for (const std::string& path : paths) {
    std::error_code error;
    if (std::filesystem::is_directory(path, error)) {
      std::vector<std::string> found;
      for (const auto& entry : std::filesystem::directory_iterator(path)) {
        std::string extension = entry.path().extension().string();
        std::transform(extension.begin(), extension.end(), extension.begin(), ::tolower);
        if (entry.is_regular_file() &&
            std::find(extensions.begin(), extensions.end(), extension) != extensions.end()) {
          found.push_back(entry.path().string());
        }
      }
      std::sort(found.begin(), found.end());
      files.insert(files.end(), found.begin(), found.end());
    } else if (std::filesystem::is_regular_file(path, error)) {
      files.push_back(path);
    } else {
      throw std::runtime_error(path + ": no such image file or directory");
    }
  }
  return files;
}

std::vector<cv::Mat> ReadGreyImages(const std::vector<std::string>& files) {
  std::vector<cv::Mat> images;
  for (const std::string& file : files) {
    cv::Mat image = cv::imread(file, cv::IMREAD_GRAYSCALE);
    if (image.empty()) throw std::runtime_error(file + ": cannot read as an image");
    images.push_back(image);
  }
  return images;
}

}  // namespace mocap

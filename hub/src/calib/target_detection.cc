// Square target detection: quadrilaterals, holed squares, grid growth, Harris corners.
#include "calib/target_detection.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <map>
#include <stdexcept>

#include <fmt/format.h>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

namespace mocap {

void TargetDetectionOptions::Check() const {
  if (!(min_square_px >= 3.0) || !std::isfinite(min_square_px)) throw std::invalid_argument("min_square_px must be >= 3");
  if (!(harris_k > 0.0 && harris_k < 0.25)) throw std::invalid_argument("harris_k must be within (0, 0.25)");
  if (harris_block < 2 || harris_block > 15) throw std::invalid_argument("harris_block must be within [2, 15]");
  if (!(match_gate > 0.0 && match_gate <= 0.5)) throw std::invalid_argument("match_gate must be within (0, 0.5]");
  if (min_points_per_face < 4) throw std::invalid_argument("min_points_per_face must be >= 4");
}

namespace {

struct Quad {
  std::array<cv::Point2d, 4> corners;  // contour order
  cv::Point2d centre;
  double side_px = 0.0;                // mean side
  std::vector<cv::Point2d> holes;      // centroids of its white holes
};

std::vector<Quad> FindQuads(const cv::Mat& gray, const TargetDetectionOptions& options) {
  cv::Mat binary;
  cv::threshold(gray, binary, 0, 255, cv::THRESH_BINARY_INV | cv::THRESH_OTSU);
  std::vector<std::vector<cv::Point>> contours;
  std::vector<cv::Vec4i> hierarchy;
  cv::findContours(binary, contours, hierarchy, cv::RETR_CCOMP, cv::CHAIN_APPROX_NONE);
  std::vector<Quad> quads;
  for (size_t i = 0; i < contours.size(); ++i) {
    if (hierarchy[i][3] >= 0) continue;  // a hole
    const double perimeter = cv::arcLength(contours[i], true);
    if (perimeter < 4.0 * options.min_square_px) continue;
    std::vector<cv::Point> polygon;
    cv::approxPolyDP(contours[i], polygon, 0.05 * perimeter, true);
    if (polygon.size() != 4 || !cv::isContourConvex(polygon)) continue;
    // The room around a target darker than the paper outlines the image itself.
    const cv::Rect box = cv::boundingRect(polygon);
    if (box.x <= 1 || box.y <= 1 || box.x + box.width >= gray.cols - 1 || box.y + box.height >= gray.rows - 1) continue;
    Quad quad;
    double sides = 0.0, shortest = 1e300;
    for (int k = 0; k < 4; ++k) {
      quad.corners[k] = cv::Point2d(polygon[k].x, polygon[k].y);
      const double side = cv::norm(polygon[k] - polygon[(k + 1) % 4]);
      sides += side;
      shortest = std::min(shortest, side);
    }
    quad.side_px = sides / 4.0;
    // Squares seen at a slant stay fairly compact; the sheet's outline or the background is not.
    if (shortest < options.min_square_px || cv::contourArea(polygon) < 0.25 * quad.side_px * quad.side_px) continue;
    quad.centre = 0.25 * (quad.corners[0] + quad.corners[1] + quad.corners[2] + quad.corners[3]);
    for (int child = hierarchy[i][2]; child >= 0; child = hierarchy[child][0]) {
      const cv::Moments m = cv::moments(contours[child]);
      if (m.m00 < 2.0) continue;  // a speck of noise
      quad.holes.emplace_back(m.m10 / m.m00, m.m01 / m.m00);
    }
    quads.push_back(quad);
  }
  return quads;
}

cv::Point2d Apply(const cv::Mat& h, const Eigen::Vector2d& uv) {
  const double x = h.at<double>(0, 0) * uv.x() + h.at<double>(0, 1) * uv.y() + h.at<double>(0, 2);
  const double y = h.at<double>(1, 0) * uv.x() + h.at<double>(1, 1) * uv.y() + h.at<double>(1, 2);
  const double w = h.at<double>(2, 0) * uv.x() + h.at<double>(2, 1) * uv.y() + h.at<double>(2, 2);
  return {x / w, y / w};
}

// One face's squares: (row, col) -> quad and the quad corner of each square corner.
struct FaceMatch {
  std::map<std::pair<int, int>, std::pair<int, std::array<int, 4>>> squares;
};

class FaceGrower {
 public:
  FaceGrower(const std::vector<Quad>& quads, const CalibrationTargetLayout& layout, const TargetDetectionOptions& options)
      : quads_(quads), layout_(layout), options_(options) {}

  // Grows the face from its holed quad whose corners 0..3 are quad corners `order`.
  FaceMatch Grow(int seed, const std::array<int, 4>& order) const {
    FaceMatch match;
    std::vector<char> used(quads_.size(), 0);
    match.squares[{0, 0}] = {seed, order};
    used[seed] = 1;
    cv::Mat h = Fit(match);
    if (h.empty()) return match;
    for (int pass = 0; pass < layout_.rows * layout_.cols; ++pass) {
      int added = 0;
      for (int row = 0; row < layout_.rows; ++row) {
        for (int col = 0; col < layout_.cols; ++col) {
          if (match.squares.count({row, col}) || !NextToMatched(match, row, col)) continue;
          added += TryMatch(h, row, col, &used, &match);
        }
      }
      if (added == 0) break;
      const cv::Mat refit = Fit(match);
      if (refit.empty()) break;
      h = refit;
    }
    return match;
  }

 private:
  static bool NextToMatched(const FaceMatch& match, int row, int col) {
    for (int dr = -1; dr <= 1; ++dr) {
      for (int dc = -1; dc <= 1; ++dc) {
        if (match.squares.count({row + dr, col + dc})) return true;
      }
    }
    return false;
  }

  int TryMatch(const cv::Mat& h, int row, int col, std::vector<char>* used, FaceMatch* match) const {
    const double pitch = layout_.square_mm + layout_.gap_mm;
    const Eigen::Vector2d centre = 0.5 * (layout_.CornerOnFace(row, col, 0) + layout_.CornerOnFace(row, col, 2));
    const cv::Point2d predicted = Apply(h, centre);
    const double pitch_px = std::min(cv::norm(Apply(h, centre + Eigen::Vector2d(pitch, 0.0)) - predicted),
                                     cv::norm(Apply(h, centre + Eigen::Vector2d(0.0, pitch)) - predicted));
    int best = -1;
    double best_distance = options_.match_gate * pitch_px;
    for (size_t q = 0; q < quads_.size(); ++q) {
      const double d = cv::norm(quads_[q].centre - predicted);
      if (!(*used)[q] && d < best_distance) {
        best = static_cast<int>(q);
        best_distance = d;
      }
    }
    if (best < 0) return 0;
    std::array<int, 4> order{};
    std::array<char, 4> taken{};
    for (int corner = 0; corner < 4; ++corner) {
      const cv::Point2d p = Apply(h, layout_.CornerOnFace(row, col, corner));
      int nearest = 0;
      for (int k = 1; k < 4; ++k) {
        if (cv::norm(quads_[best].corners[k] - p) < cv::norm(quads_[best].corners[nearest] - p)) nearest = k;
      }
      if (taken[nearest]) return 0;  // corners do not map one to one: not this square
      taken[nearest] = 1;
      order[corner] = nearest;
    }
    (*used)[best] = 1;
    match->squares[{row, col}] = {best, order};
    return 1;
  }

  cv::Mat Fit(const FaceMatch& match) const {
    std::vector<cv::Point2d> face, image;
    for (const auto& [cell, square] : match.squares) {
      for (int corner = 0; corner < 4; ++corner) {
        const Eigen::Vector2d uv = layout_.CornerOnFace(cell.first, cell.second, corner);
        face.emplace_back(uv.x(), uv.y());
        image.push_back(quads_[square.first].corners[square.second[corner]]);
      }
    }
    return cv::findHomography(face, image, 0);
  }

  const std::vector<Quad>& quads_;
  const CalibrationTargetLayout& layout_;
  const TargetDetectionOptions& options_;
};

// The face's holed quad: exactly one quad with `holes` holes.
int FindSeed(const std::vector<Quad>& quads, size_t holes, TargetFace face) {
  int seed = -1, count = 0;
  for (size_t q = 0; q < quads.size(); ++q) {
    if (quads[q].holes.size() != holes) continue;
    seed = static_cast<int>(q);
    ++count;
  }
  if (count != 1)
    throw std::runtime_error(fmt::format(
        "the {} face's first square ({} white hole{}) was {} ({} dark squares seen): the whole target must be in "
        "view, sharp and evenly lit",
        TargetFaceName(face), holes, holes == 1 ? "" : "s", count == 0 ? "not found" : "found more than once",
        quads.size()));
  return seed;
}

// Largest distance (px) from a hole the layout puts in the face's first square, mapped into the
// image through that square's corners taken in `order`, to the nearest hole seen in it.
double HoleError(const Quad& quad, const std::array<int, 4>& order, const CalibrationTargetLayout& layout,
                 TargetFace face) {
  std::vector<cv::Point2f> square, image;  // getPerspectiveTransform takes single precision
  for (int corner = 0; corner < 4; ++corner) {
    const Eigen::Vector2d uv = layout.CornerOnFace(0, 0, corner);
    square.emplace_back(static_cast<float>(uv.x()), static_cast<float>(uv.y()));
    image.emplace_back(quad.corners[order[corner]]);
  }
  const cv::Mat h = cv::getPerspectiveTransform(square, image);
  double worst = 0.0;
  for (const Eigen::Vector2d& hole : layout.HoleCentres(face)) {
    const cv::Point2d predicted = Apply(h, hole);
    double nearest = std::numeric_limits<double>::infinity();
    for (const cv::Point2d& seen : quad.holes) nearest = std::min(nearest, cv::norm(seen - predicted));
    worst = std::max(worst, nearest);
  }
  return worst;
}

// Which quad corner is the square's corner 0, and which way round the face runs. The holes sit
// on the square's diagonal from corner 0 (calibration_target.h); their position is checked
// through the square's own homography, not by the nearest corner in the image, since a square
// seen at a slant (a floor face from the side) can bring another corner nearer to them. The
// holes lie on the diagonal, so the face's two turning directions fit them alike: both are
// grown and the one that explains more squares kept.
FaceMatch MatchFace(const std::vector<Quad>& quads, int seed, const FaceGrower& grower,
                    const CalibrationTargetLayout& layout, TargetFace face) {
  const Quad& quad = quads[seed];
  std::vector<std::pair<double, std::array<int, 4>>> orders;
  for (int first = 0; first < 4; ++first) {
    for (const int step : {1, 3}) {
      const std::array<int, 4> order = {first, (first + step) % 4, (first + 2 * step) % 4, (first + 3 * step) % 4};
      orders.emplace_back(HoleError(quad, order, layout, face), order);
    }
  }
  std::sort(orders.begin(), orders.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  // The orders whose holes fit within a tenth of the square's side (at least the best two: the
  // two directions of the best corner).
  const double gate = std::max(0.1 * quad.side_px, orders[1].first);
  FaceMatch best;
  for (const auto& [error, order] : orders) {
    if (error > gate) break;
    FaceMatch match = grower.Grow(seed, order);
    if (match.squares.size() > best.squares.size()) best = std::move(match);
  }
  return best;
}

}  // namespace

TargetDetection DetectTargetPoints(const cv::Mat& gray, const CalibrationTargetLayout& layout,
                                   const TargetDetectionOptions& options) {
  options.Check();
  layout.Check();
  if (gray.empty() || gray.type() != CV_8UC1) throw std::runtime_error("the image must be 8-bit grey and not empty");
  if (gray.cols < 16 || gray.rows < 16) throw std::runtime_error("the image is smaller than 16 x 16 px");
  const std::vector<Quad> quads = FindQuads(gray, options);
  TargetDetection detection;
  detection.squares_seen = static_cast<int>(quads.size());
  const FaceGrower grower(quads, layout, options);

  cv::Mat response;
  cv::Mat gray_float;
  gray.convertTo(gray_float, CV_32F);
  cv::cornerHarris(gray_float, response, options.harris_block, 3, options.harris_k);

  std::map<int, cv::Point2d> found;  // point index -> pixel
  for (const TargetFace face : {TargetFace::kWall, TargetFace::kFloor}) {
    const int seed = FindSeed(quads, face == TargetFace::kWall ? 1 : 2, face);
    const FaceMatch match = MatchFace(quads, seed, grower, layout, face);
    int points = 0;
    for (const auto& [cell, square] : match.squares) {
      const Quad& quad = quads[square.first];
      // Harris near the quadrilateral's vertex; the window stays within a fifth of the square,
      // clear of the square's other corners and of the holes.
      const int search = std::max(2, static_cast<int>(std::lround(0.12 * quad.side_px)));
      const int window = std::max(2, static_cast<int>(std::lround(0.15 * quad.side_px)));
      for (int corner = 0; corner < 4; ++corner) {
        const cv::Point2d coarse = quad.corners[square.second[corner]];
        const cv::Point start(static_cast<int>(std::lround(coarse.x)), static_cast<int>(std::lround(coarse.y)));
        cv::Point harris = start;
        float best_response = -1e30f;
        for (int y = start.y - search; y <= start.y + search; ++y) {
          for (int x = start.x - search; x <= start.x + search; ++x) {
            if (x < 0 || y < 0 || x >= response.cols || y >= response.rows) continue;
            if (response.at<float>(y, x) > best_response) {
              best_response = response.at<float>(y, x);
              harris = cv::Point(x, y);
            }
          }
        }
        const int margin = window + 2;
        if (harris.x < margin || harris.y < margin || harris.x >= gray.cols - margin || harris.y >= gray.rows - margin)
          continue;  // too close to the image border to refine
        std::vector<cv::Point2f> refined = {cv::Point2f(static_cast<float>(harris.x), static_cast<float>(harris.y))};
        cv::cornerSubPix(gray, refined, cv::Size(window, window), cv::Size(-1, -1),
                         cv::TermCriteria(cv::TermCriteria::EPS + cv::TermCriteria::COUNT, 50, 1e-4));
        const cv::Point2d pixel(refined[0].x, refined[0].y);
        detection.max_harris_shift_px = std::max(detection.max_harris_shift_px, cv::norm(pixel - cv::Point2d(harris)));
        found[layout.PointIndex(face, cell.first, cell.second, corner)] = pixel;
        ++points;
      }
    }
    if (points < options.min_points_per_face)
      throw std::runtime_error(fmt::format("only {} points of the {} face were found (need {}): move the camera so "
                                           "that the target fills more of the image",
                                           points, TargetFaceName(face), options.min_points_per_face));
    (face == TargetFace::kWall ? detection.wall_points : detection.floor_points) = points;
  }
  for (const auto& [index, pixel] : found) {
    ControlPoint point;
    point.point_in_world = layout.PointInWorld(index);
    point.pixel = Eigen::Vector2d(pixel.x, pixel.y);
    detection.points.push_back(point);
    detection.indices.push_back(index);
  }
  return detection;
}

void WriteControlPoints(const std::vector<ControlPoint>& points, const std::string& path, const std::string& comment) {
  std::ofstream out(path);
  if (!out) throw std::runtime_error(path + ": cannot be written");
  out << "# " << comment << "\n# x y z (mm) u v (px)\n";
  for (const ControlPoint& p : points) {
    out << fmt::format("{:.4f} {:.4f} {:.4f} {:.4f} {:.4f}\n", p.point_in_world.x(), p.point_in_world.y(),
                       p.point_in_world.z(), p.pixel.x(), p.pixel.y());
  }
  out.close();
  if (!out) throw std::runtime_error(path + ": write failed");
}

}  // namespace mocap

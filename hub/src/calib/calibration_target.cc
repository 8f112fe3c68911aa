// Geometry, SVG and JSON of seed 000's two-face square target.
#include "calib/calibration_target.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "util/json_file.h"

namespace mocap {

const char* TargetFaceName(TargetFace face) { return face == TargetFace::kWall ? "wall" : "floor"; }

void CalibrationTargetLayout::Check() const {
  if (rows < 2 || rows > 50) throw std::invalid_argument("target rows must be within [2, 50]");
  if (cols < 2 || cols > 50) throw std::invalid_argument("target cols must be within [2, 50]");
  if (!std::isfinite(square_mm) || square_mm < 4.0 || square_mm > 500.0)
    throw std::invalid_argument("target square_mm must be within [4, 500]");
  if (!std::isfinite(gap_mm) || gap_mm < 0.25 * square_mm || gap_mm > 500.0)
    throw std::invalid_argument("target gap_mm must be within [square_mm / 4, 500] (squares must stay apart)");
  if (!std::isfinite(edge_mm) || edge_mm < 0.0 || edge_mm > 500.0)
    throw std::invalid_argument("target edge_mm must be within [0, 500]");
  if (!std::isfinite(fold_mm) || fold_mm < 0.0 || fold_mm > 500.0)
    throw std::invalid_argument("target fold_mm must be within [0, 500]");
  if (PageWidthMm() > 2000.0 || PageHeightMm() > 2000.0)
    throw std::invalid_argument(fmt::format("target page {:.0f} x {:.0f} mm is larger than 2 m", PageWidthMm(),
                                            PageHeightMm()));
}

double CalibrationTargetLayout::PageWidthMm() const { return 2.0 * edge_mm + cols * square_mm + (cols - 1) * gap_mm; }
double CalibrationTargetLayout::HalfHeightMm() const {
  return fold_mm + rows * square_mm + (rows - 1) * gap_mm + edge_mm;
}
double CalibrationTargetLayout::PageHeightMm() const { return 2.0 * HalfHeightMm(); }

Eigen::Vector2d CalibrationTargetLayout::CornerOnFace(int row, int col, int corner) const {
  const double u0 = edge_mm + col * (square_mm + gap_mm);
  const double v0 = fold_mm + row * (square_mm + gap_mm);
  const double du = (corner == 1 || corner == 2) ? square_mm : 0.0;
  const double dv = (corner == 2 || corner == 3) ? square_mm : 0.0;
  return {u0 + du, v0 + dv};
}

int CalibrationTargetLayout::PointIndex(TargetFace face, int row, int col, int corner) const {
  return ((static_cast<int>(face) * rows + row) * cols + col) * 4 + corner;
}

Eigen::Vector3d CalibrationTargetLayout::FaceToWorld(TargetFace face, const Eigen::Vector2d& uv) {
  return face == TargetFace::kWall ? Eigen::Vector3d(uv.x(), 0.0, uv.y()) : Eigen::Vector3d(uv.x(), uv.y(), 0.0);
}

Eigen::Vector3d CalibrationTargetLayout::PointInWorld(int index) const {
  const int corner = index % 4;
  const int col = (index / 4) % cols;
  const int row = (index / (4 * cols)) % rows;
  const TargetFace face = index / PointsPerFace() == 0 ? TargetFace::kWall : TargetFace::kFloor;
  return FaceToWorld(face, CornerOnFace(row, col, corner));
}

std::vector<Eigen::Vector2d> CalibrationTargetLayout::HoleCentres(TargetFace face) const {
  const Eigen::Vector2d corner0 = CornerOnFace(0, 0, 0);
  const Eigen::Vector2d diagonal(square_mm, square_mm);
  if (face == TargetFace::kWall) return {corner0 + 0.3 * diagonal};
  return {corner0 + 0.25 * diagonal, corner0 + 0.5 * diagonal};
}

bool CalibrationTargetLayout::InkAt(TargetFace face, const Eigen::Vector2d& uv) const {
  const double pitch = square_mm + gap_mm;
  const double u = uv.x() - edge_mm, v = uv.y() - fold_mm;
  if (u < 0.0 || v < 0.0) return false;
  const int col = static_cast<int>(u / pitch), row = static_cast<int>(v / pitch);
  if (col >= cols || row >= rows) return false;
  if (u - col * pitch > square_mm || v - row * pitch > square_mm) return false;
  if (row == 0 && col == 0) {
    const double half = 0.5 * HoleSideMm();
    for (const Eigen::Vector2d& hole : HoleCentres(face)) {
      if (std::abs(uv.x() - hole.x()) <= half && std::abs(uv.y() - hole.y()) <= half) return false;
    }
  }
  return true;
}

std::string TargetSvg(const CalibrationTargetLayout& layout) {
  layout.Check();
  const double width = layout.PageWidthMm(), height = layout.PageHeightMm(), fold = layout.HalfHeightMm();
  std::ostringstream svg;
  svg << fmt::format(
      "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
      "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{0:.3f}mm\" height=\"{1:.3f}mm\" "
      "viewBox=\"0 0 {0:.3f} {1:.3f}\">\n"
      "<!-- mocap calibration target (seed 000): print at 100 %, fold along the dashed line to a right "
      "angle, upper half standing (wall), lower half flat (floor). Squares {2:g} mm, gaps {3:g} mm. -->\n"
      "<rect x=\"0\" y=\"0\" width=\"{0:.3f}\" height=\"{1:.3f}\" fill=\"white\"/>\n",
      width, height, layout.square_mm, layout.gap_mm);
  for (const TargetFace face : {TargetFace::kWall, TargetFace::kFloor}) {
    // Page y grows downwards: the wall's v runs up from the fold, the floor's down.
    auto page_y = [&](double v) { return face == TargetFace::kWall ? fold - v : fold + v; };
    for (int row = 0; row < layout.rows; ++row) {
      for (int col = 0; col < layout.cols; ++col) {
        const Eigen::Vector2d a = layout.CornerOnFace(row, col, 0), c = layout.CornerOnFace(row, col, 2);
        const double top = std::min(page_y(a.y()), page_y(c.y()));
        svg << fmt::format("<rect x=\"{:.3f}\" y=\"{:.3f}\" width=\"{:.3f}\" height=\"{:.3f}\" fill=\"black\"/>\n",
                           a.x(), top, layout.square_mm, layout.square_mm);
      }
    }
    const double half = 0.5 * layout.HoleSideMm();
    for (const Eigen::Vector2d& hole : layout.HoleCentres(face)) {
      svg << fmt::format("<rect x=\"{:.3f}\" y=\"{:.3f}\" width=\"{:.3f}\" height=\"{:.3f}\" fill=\"white\"/>\n",
                         hole.x() - half, page_y(hole.y()) - half, layout.HoleSideMm(), layout.HoleSideMm());
    }
  }
  svg << fmt::format(
      "<line x1=\"0\" y1=\"{0:.3f}\" x2=\"{1:.3f}\" y2=\"{0:.3f}\" stroke=\"#999\" stroke-width=\"0.2\" "
      "stroke-dasharray=\"2 2\"/>\n</svg>\n",
      fold, width);
  return svg.str();
}

nlohmann::json TargetToJson(const CalibrationTargetLayout& layout) {
  layout.Check();
  nlohmann::json points = nlohmann::json::array();
  for (const TargetFace face : {TargetFace::kWall, TargetFace::kFloor}) {
    for (int row = 0; row < layout.rows; ++row) {
      for (int col = 0; col < layout.cols; ++col) {
        for (int corner = 0; corner < 4; ++corner) {
          const int index = layout.PointIndex(face, row, col, corner);
          const Eigen::Vector3d p = layout.PointInWorld(index);
          points.push_back({{"index", index},
                            {"face", TargetFaceName(face)},
                            {"row", row},
                            {"col", col},
                            {"corner", corner},
                            {"xyz", {p.x(), p.y(), p.z()}}});
        }
      }
    }
  }
  return {{"version", 1},
          {"type", "seed000-squares"},
          {"units", "mm"},
          {"layout",
           {{"rows", layout.rows},
            {"cols", layout.cols},
            {"square_mm", layout.square_mm},
            {"gap_mm", layout.gap_mm},
            {"edge_mm", layout.edge_mm},
            {"fold_mm", layout.fold_mm}}},
          {"page_mm", {layout.PageWidthMm(), layout.PageHeightMm()}},
          {"points", points}};
}

CalibrationTargetLayout TargetFromJson(const nlohmann::json& document, const std::string& source) {
  auto fail = [&](const std::string& what) { return std::runtime_error(source + ": " + what); };
  if (!document.is_object()) throw fail("not a JSON object");
  if (!document.contains("version") || !document["version"].is_number_integer() || document["version"] != 1)
    throw fail("\"version\" must be 1");
  if (!document.contains("type") || document["type"] != "seed000-squares")
    throw fail("\"type\" must be \"seed000-squares\" (a target written by calibrate target)");
  if (!document.contains("layout") || !document["layout"].is_object()) throw fail("no \"layout\" object");
  const nlohmann::json& l = document["layout"];
  auto integer = [&](const char* key) {
    if (!l.contains(key) || !l[key].is_number_integer()) throw fail(std::string("layout.") + key + " must be an integer");
    const long long value = l[key].get<long long>();
    if (value < -1000000 || value > 1000000) throw fail(std::string("layout.") + key + " is out of range");
    return static_cast<int>(value);
  };
  auto number = [&](const char* key) {
    if (!l.contains(key) || !l[key].is_number()) throw fail(std::string("layout.") + key + " must be a number");
    return l[key].get<double>();
  };
  CalibrationTargetLayout layout;
  layout.rows = integer("rows");
  layout.cols = integer("cols");
  layout.square_mm = number("square_mm");
  layout.gap_mm = number("gap_mm");
  layout.edge_mm = number("edge_mm");
  layout.fold_mm = number("fold_mm");
  try {
    layout.Check();
  } catch (const std::invalid_argument& error) {
    throw fail(error.what());
  }
  return layout;
}

CalibrationTargetLayout ReadTargetJson(const std::string& path) { return TargetFromJson(ReadJsonFile(path), path); }

}  // namespace mocap

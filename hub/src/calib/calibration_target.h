// Seed 000's calibration target (sections 3.3.1 and 3.5.1): isolated black squares, whose
// corners are the control points, on two faces at a right angle so that the points are not
// coplanar (the DLT needs that). One printable page holds both faces: the half above the fold
// line stands up as the wall (plane y = 0, z up), the half below lies flat as the floor (plane
// z = 0, y towards the camera); x runs along the fold from the page's left edge. Squares are
// numbered per face by row (away from the fold) and column; a square's corners 0-3 run from its
// fold-side left corner (+x first, then away from the fold). The first square of each face
// carries white holes near its corner 0 (one on the wall, two on the floor), which name the face
// and orient its grid for the detector (target_detection.h).
//
// Pure functions; Check() and the JSON reader throw std::invalid_argument / std::runtime_error
// ("<source>: <what>") on bad layouts and malformed files.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json_fwd.hpp>

namespace mocap {

enum class TargetFace { kWall = 0, kFloor = 1 };
const char* TargetFaceName(TargetFace face);  // "wall", "floor"

struct CalibrationTargetLayout {
  int rows = 3;             // squares away from the fold, per face
  int cols = 5;             // squares along the fold
  double square_mm = 20.0;  // side of a square
  double gap_mm = 15.0;     // white between neighbouring squares
  double edge_mm = 15.0;    // page edge to the outer squares
  double fold_mm = 10.0;    // fold line to the first row

  // Throws std::invalid_argument naming the bad value (sizes must be printable: a page of at
  // most 2 m, at least 2 x 2 squares per face, holes of at least 0.5 mm).
  void Check() const;

  double PageWidthMm() const;
  double HalfHeightMm() const;  // one face: fold to page edge
  double PageHeightMm() const;
  int PointsPerFace() const { return rows * cols * 4; }
  int NumPoints() const { return 2 * PointsPerFace(); }

  // Face coordinates (mm): u along the fold from the page's left edge, v away from the fold.
  Eigen::Vector2d CornerOnFace(int row, int col, int corner) const;
  // Point index: face, row, column, corner in that order of significance.
  int PointIndex(TargetFace face, int row, int col, int corner) const;
  Eigen::Vector3d PointInWorld(int index) const;
  static Eigen::Vector3d FaceToWorld(TargetFace face, const Eigen::Vector2d& uv);

  // Hole squares of a face's first square: centres (face coordinates) and side, mm.
  std::vector<Eigen::Vector2d> HoleCentres(TargetFace face) const;
  double HoleSideMm() const { return 0.15 * square_mm; }
  // True where the face's paper is printed black (inside a square, outside its holes).
  bool InkAt(TargetFace face, const Eigen::Vector2d& uv) const;
};

// The page as SVG (mm units, squares as black rectangles, holes white, the fold as a dashed
// grey line with a caption).
std::string TargetSvg(const CalibrationTargetLayout& layout);

// {"version": 1, "type": "seed000-squares", "units": "mm", "layout": {...}, "points":
// [{"index", "face", "row", "col", "corner", "xyz": [x, y, z]}, ...]}
nlohmann::json TargetToJson(const CalibrationTargetLayout& layout);
// Reads the layout back (points are derived from it, not read); source names the origin in
// errors. Throws std::runtime_error on malformed documents or layouts that fail Check().
CalibrationTargetLayout TargetFromJson(const nlohmann::json& document, const std::string& source);
CalibrationTargetLayout ReadTargetJson(const std::string& path);

}  // namespace mocap

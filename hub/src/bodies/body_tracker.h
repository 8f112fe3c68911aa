// Rigid bodies in every frame: which of the frame's anonymous 3D points belong to which body
// (identity from inter-marker distances), and each body's 6-DoF pose by a least-squares fit
// with outliers rejected.
// - A body being tracked is matched first: its pose predicted at constant velocity, each marker
//   taken by the nearest free point within `track_gate_mm`, the fit repeated without markers
//   farther than `max_marker_error_mm` from it; it continues with `min_markers_continue`.
// - A body not tracked is searched for: every triangle of its markers against the triangles of
//   free points with the same side lengths (within `distance_tolerance_mm`), each hypothesis
//   fitted and scored by how many of the body's markers land on free points; the best one
//   with at least `min_markers_start` markers (all of a 3-marker body's) wins: three loose
//   markers form a body's triangle by chance far more often than four its shape.
// - Through occlusions of up to `predict_frames` frames the predicted pose is reported, marked
//   predicted; after that the body is lost until found again.
// Several bodies and loose markers may be close together: a point serves one body at most, and
// bodies already tracked choose first. Pure: no clock, no I/O.
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "bodies/body_definition.h"

namespace mocap {

struct BodyTrackerOptions {
  double distance_tolerance_mm = 3.0;
  double max_marker_error_mm = 3.0;
  double track_gate_mm = 20.0;
  size_t min_markers_start = 4;     // (or all of a body's markers when it has fewer)
  size_t min_markers_continue = 3;
  int predict_frames = 10;
  size_t max_points = 4096;  // more points than this in one frame: only tracked bodies continue
  void Check() const;        // throws std::invalid_argument
};

// Why a body was not fitted in a frame (BodyPose::miss), so that an operator is told the cause.
enum class BodyMiss {
  kNone,              // fitted
  kTooFewPoints,      // fewer free points in the frame than markers needed to find it
  kNoShape,           // no three free points with the sides of any of its triangles (within tolerance)
  kTooFewMarkers,     // its triangles were found, but too few of its other markers landed on points
  kCrowded,           // more points than max_points: only bodies already tracked continue
};
const char* BodyMissText(BodyMiss miss);

struct BodyPose {
  bool tracked = false;     // fitted to this frame's points
  bool predicted = false;   // not seen this frame: the pose predicted from the last frames
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();  // body -> world
  Eigen::Vector3d position = Eigen::Vector3d::Zero();               // the body frame's origin, world mm
  Eigen::Vector3d pivot = Eigen::Vector3d::Zero();                  // the pivot in the world, mm
  double mean_error_mm = 0.0;  // mean distance of the fitted markers from their points
  size_t markers = 0;          // markers fitted
  std::vector<int> point_of_marker;  // per body marker: the frame's point index, -1 when none
  BodyMiss miss = BodyMiss::kNone;   // not tracked: why the search failed
};

class BodyTracker {
 public:
  // Throws std::invalid_argument for bad options or an empty body.
  BodyTracker(std::vector<RigidBodyDefinition> bodies, const BodyTrackerOptions& options = {});

  // One frame's points (any order, any number); frames must come in order. Returns one pose
  // per body (in the definitions' order). `owner`, when given, gets per point the body that
  // used it, or -1.
  std::vector<BodyPose> Update(const std::vector<Eigen::Vector3d>& points, std::vector<int>* owner = nullptr);

  const std::vector<RigidBodyDefinition>& bodies() const { return bodies_; }

 private:
  struct State {
    bool known = false;         // has a last pose
    int frames_since = 0;       // since it was last fitted
    Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
    Eigen::Vector3d translation = Eigen::Vector3d::Zero();
    Eigen::Vector3d velocity = Eigen::Vector3d::Zero();      // mm per frame
    Eigen::Vector3d angular = Eigen::Vector3d::Zero();       // rotation vector per frame
  };
  bool Follow(size_t body, const std::vector<Eigen::Vector3d>& points, const std::vector<int>& owner, BodyPose* pose);
  // Not found: *miss says why.
  bool Search(size_t body, const std::vector<Eigen::Vector3d>& points, const std::vector<int>& owner, BodyPose* pose,
              BodyMiss* miss);
  bool FitAndPrune(size_t body, const std::vector<Eigen::Vector3d>& points, BodyPose* pose, size_t min_markers);
  void Remember(size_t body, const BodyPose& pose);

  std::vector<RigidBodyDefinition> bodies_;
  BodyTrackerOptions options_;
  std::vector<State> states_;
};

}  // namespace mocap

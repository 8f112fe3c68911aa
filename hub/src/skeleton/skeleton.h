// A skeleton: segments in a tree, each joined to its parent by a joint of 1-3 rotational degrees of
// freedom (Euler angles about the segment's own axes, applied in the listed order, with limits),
// and markers attached to segments with an offset and a weight. The root segment also translates.
// Skeleton space: +y up, +z the subject's forward, +x the subject's left (BVH's usual frame). In
// the rest pose (all angles zero) every segment's frame is parallel to the root's, as BVH and
// Acclaim ASF assume; a joint's centre sits at `offset` in its parent's frame. Millimetres.
// Kept as JSON, editable by hand:
//   {"version": 1, "type": "skeleton", "calibrated": false,
//    "segments": [{"name": "Hips", "parent": null, "offset": [0,0,0],
//                  "dofs": [{"axis": "y", "min": -180, "max": 180}, ...], "end": [0,0,0]},
//                 {"name": "LeftLeg", "parent": "LeftUpLeg", "offset": [0,-420,0], "bone": true,
//                  "reference_zero": false, "dofs": [{"axis": "x", "min": -10, "max": 160}]}, ...],
//    "markers": [{"name": "LKNE", "segment": "LeftUpLeg", "offset": [50,-420,0], "weight": 1}, ...]}
// "bone": the offset's direction is fixed (calibration fits its length only): a limb's bone.
// "reference_zero": the segment's frame is not set by its joints or bones (trunk, head, feet):
// calibration fixes it by taking this joint's angles as zero in the trial's reference frame.
// "end": where the segment ends when no child does (BVH End Site, ASF bone length).
// Errors: std::runtime_error "<source>: <reason>" for files (the io layer's rule).
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json_fwd.hpp>

namespace mocap {

struct JointDof {
  int axis = 0;  // 0 x, 1 y, 2 z of the segment's own frame
  double min_deg = -180.0, max_deg = 180.0;
};

struct SkeletonSegment {
  std::string name;
  int parent = -1;  // index of an earlier segment; -1 for the root (segment 0 only)
  Eigen::Vector3d offset = Eigen::Vector3d::Zero();  // joint centre in the parent's frame
  bool bone = false;
  bool reference_zero = false;
  std::vector<JointDof> dofs;  // the root has exactly 3, the others 1-3
  Eigen::Vector3d end = Eigen::Vector3d::Zero();
};

struct SkeletonMarker {
  std::string name;
  int segment = 0;
  Eigen::Vector3d offset = Eigen::Vector3d::Zero();  // in the segment's frame, from its joint centre
  double weight = 1.0;
};

struct Skeleton {
  bool calibrated = false;
  std::vector<SkeletonSegment> segments;
  std::vector<SkeletonMarker> markers;

  size_t NumSegments() const { return segments.size(); }
  // The pose vector's size: the root's translation (3), then every segment's dofs in order.
  size_t NumPoseParameters() const;
  // Where segment s's first angle sits in the pose vector.
  size_t FirstDof(size_t s) const;
  int FindSegment(const std::string& name) const;
  int FindMarker(const std::string& name) const;
  // Children of each segment, in index order.
  std::vector<std::vector<int>> Children() const;
  // Throws std::invalid_argument naming the field, value and rule.
  void Check() const;
};

// Reader limits: larger skeletons are refused (memory stays bounded).
constexpr size_t kMaxSkeletonSegments = 200;
constexpr size_t kMaxSkeletonMarkers = 1000;

char AxisName(int axis);

nlohmann::json SkeletonToJson(const Skeleton& skeleton);
Skeleton SkeletonFromJson(const nlohmann::json& document, const std::string& source);
Skeleton ReadSkeletonFile(const std::string& path);
void WriteSkeletonFile(const Skeleton& skeleton, const std::string& path);

}  // namespace mocap

// Data packets of the Qualisys RT protocol from the hub's LiveFrame: the 3D, 3D-no-labels, 6D
// and 6D-Euler components and their residual variants, in the little-endian layout.
//
// How the hub's result maps onto them:
//  - With a marker set (serve --labels) the labels are its names, in its order, and a point
//    carries the label of its name. Without one, labels are the confirmed tracks in the order
//    they were first confirmed, named T and their id (T17 for the track every stream calls 17).
//    The list only grows, so a
//    client that read the labels earlier still indexes the labelled components correctly; a
//    label not seen in a frame is NaN (all bits set, as the protocol says).
//  - 3D no labels carries every point of the frame, confirmed or not (the hub's labels are
//    tracks, not an identified marker set): ID = the point's track id (LivePoint id, the same
//    from the track's first frame on, provisional or confirmed; past 2^32 - 1 it wraps to 1), 0
//    for a point no track took.
//  - Residuals are the hub's reprojection RMS in pixels for points, the body fit's mean error
//    in mm for bodies.
//  - 6D lists the bodies seen so far (by id); a body not tracked in the frame is NaN. Rotation
//    matrices are body -> world, sent column by column (Rot_1_1, Rot_2_1, Rot_3_1, Rot_1_2, ...,
//    the order of the protocol's own camera matrices). Euler angles (degrees) are roll about x,
//    pitch about y, yaw about z with R = Rx(roll) * Ry(pitch) * Rz(yaw).
//  - Timestamp: the frame's trigger time on the session clock in microseconds (CLOCK_REALTIME
//    on a disciplined installation); the 2D drop rate is the frame set's missing camera frames
//    per thousand.
// Pure code: no I/O, no clock.
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "pipeline/live_frame.h"

namespace mocap::stream::qtm {

// Labels and bodies seen so far: one per server, updated from every frame before encoding.
class RtNames {
 public:
  // Bounds keep a broken tracker from growing the tables without end.
  static constexpr size_t kMaxLabels = 4096;
  static constexpr size_t kMaxBodies = 1024;

  void Update(const pipeline::LiveFrame& frame);
  // The labels are a marker set's names from now on (serve --labels: known before any frame).
  void UseMarkerSet(std::shared_ptr<const std::vector<std::string>> names) { set_names_ = std::move(names); }
  size_t label_count() const { return set_names_ ? set_names_->size() : tracks_.size(); }
  std::string label_name(size_t label) const;
  // Label index of a point, -1 if it has none.
  int LabelOf(const pipeline::LivePoint& point) const;
  static std::string TrackName(uint64_t id);
  // Bodies by id: id -> name.
  const std::map<uint32_t, std::string>& bodies() const { return bodies_; }

 private:
  std::shared_ptr<const std::vector<std::string>> set_names_;  // the marker set's names, or null
  std::vector<uint64_t> tracks_;  // confirmed tracks' ids, in the order first seen
  std::map<uint64_t, int> index_of_track_;
  std::map<uint32_t, std::string> bodies_;
};

// Roll, pitch, yaw in degrees of a body -> world rotation (see above).
Eigen::Vector3d EulerDegrees(const Eigen::Matrix3d& rotation);

// One data packet (header included) with the components in `components` (rt_command.h bits),
// in ascending protocol type order. expected_cameras: the rig's camera count (for the drop rate).
std::string EncodeDataPacket(const pipeline::LiveFrame& frame, uint32_t components, const RtNames& names,
                             int expected_cameras);

}  // namespace mocap::stream::qtm

// One frame's 3D result as every consumer sees it: each point with its residual, views and
// identity, the confirmed samples for writers of labelled files, the rigid bodies' poses, the
// skeletons' bones. Made by LiveReconstruction (live_reconstruction.h) and its stages
// (live_skeleton.h); carried out by stream/ and api/, written by capture.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "track/tracker.h"

namespace mocap::pipeline {

struct LivePoint {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  // world, mm
  double rms_px = 0.0;                 // reprojection RMS over its views (the hub's rms_px)
  int views = 0;
  int marker = -1;                     // confirmed track's marker (0-based column), else -1
  uint64_t id = 0;                     // its track's id from the first frame on (tracker.h), 0 when none
  int label = -1;                      // index into LiveFrame::label_names (--labels), -1: unnamed
  bool provisional() const { return marker < 0; }
};

// A rigid body's pose in one frame (filled once rigid bodies exist; streams carry them).
struct LiveBody {
  uint32_t id = 0;                     // 1-based, in the bodies file's order
  std::string name;
  bool tracked = false;                // fitted to this frame's points
  bool predicted = false;              // not seen: the pose predicted through a short occlusion
  Eigen::Vector3d position = Eigen::Vector3d::Zero();               // world, mm
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();  // body -> world
  double mean_error_mm = 0.0;          // mean distance of its fitted markers
  int markers = 0;                     // markers fitted
};

// A live skeleton's segments (serve --skeleton), shared by every frame: names and tree.
struct LiveSkeletonModel {
  std::string name;                    // the subject (the skeleton file's name without .json)
  std::vector<std::string> bones;      // segment names, parents before children
  std::vector<int> parents;            // per bone: its parent's index, -1 for the root
  std::vector<Eigen::Vector3d> offsets;  // per bone: its joint centre in its parent's frame, mm
};

// One segment's pose in one frame: its joint centre and its frame's orientation. The segment's
// frame is skeleton space at rest (+y up, +z the subject's forward, +x its left;
// skeleton/skeleton.h), so a subject standing at rest facing world +z with +y up has identity
// orientations.
struct LiveBone {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();               // world, mm
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();  // segment -> world
};

// The skeleton's fit in one frame. Bones are present only when `solved`; otherwise `state` says
// why not and no pose is given (a client never sees a stale pose as current).
struct LiveSkeleton {
  std::shared_ptr<const LiveSkeletonModel> model;
  bool solved = false;
  const char* state = "";              // "solved", "too few markers", "not solved"
  int markers = 0;                     // named markers of the skeleton seen in the frame
  double rms_mm = 0.0, max_mm = 0.0;   // the fit's marker residuals (when solved)
  double solve_ms = 0.0;               // the solve's own time on the hub
  std::vector<LiveBone> bones;         // per model bone when solved, else empty
};

struct LiveFrame {
  uint64_t frame_number = 0;
  uint64_t trigger_time_ns = 0;        // earliest camera trigger time (session clock), 0 if none
  uint64_t last_receive_ns = 0;        // hub clock: the last datagram of the set arrived
  uint64_t publish_ns = 0;             // hub clock: the result was complete
  int cameras = 0;                     // camera frames in the set
  std::vector<LivePoint> points;
  std::vector<TrackSample> samples;    // confirmed markers' samples (may reach back in time)
  std::vector<LiveBody> bodies;        // one per defined rigid body, in the bodies file's order
  std::vector<LiveSkeleton> skeletons; // serve --skeleton: one per subject (none without)
  // The marker set's names (serve --labels), shared by every frame; null without a marker set.
  std::shared_ptr<const std::vector<std::string>> label_names;
};

}  // namespace mocap::pipeline

// One frame's 3D result as every consumer sees it: each point with its residual, views and
// identity, the confirmed samples for writers of labelled files, the rigid bodies' poses. Made by
// LiveReconstruction (live_reconstruction.h); carried out by stream/ and api/, written by capture.
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

struct LiveFrame {
  uint64_t frame_number = 0;
  uint64_t trigger_time_ns = 0;        // earliest camera trigger time (session clock), 0 if none
  uint64_t last_receive_ns = 0;        // hub clock: the last datagram of the set arrived
  uint64_t publish_ns = 0;             // hub clock: the result was complete
  int cameras = 0;                     // camera frames in the set
  std::vector<LivePoint> points;
  std::vector<TrackSample> samples;    // confirmed markers' samples (may reach back in time)
  std::vector<LiveBody> bodies;        // one per defined rigid body, in the bodies file's order
  // The marker set's names (serve --labels), shared by every frame; null without a marker set.
  std::shared_ptr<const std::vector<std::string>> label_names;
};

}  // namespace mocap::pipeline

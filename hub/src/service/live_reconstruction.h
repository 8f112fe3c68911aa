// Every frame set's 3D result the moment it is assembled, shared by `serve` and `record`:
// reconstruction with the tracker's predictions, tracking, and one LiveFrame holding every
// point with whose it is. Nothing is held back: a point of a track not yet confirmed is
// published as provisional (with the tentative track's serial) in its own frame, a point no
// track took is published without an id; the confirmed samples (with the frames of a track
// confirmed now) come with it for writers of labelled files.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "geometry/camera.h"
#include "ingest/camera_frame.h"
#include "bodies/body_live_filter.h"
#include "labels/marker_labeller.h"
#include "recon/reconstructor.h"
#include "track/tracker.h"

namespace mocap::service {

struct LivePoint {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  // world, mm
  double rms_px = 0.0;                 // reprojection RMS over its views (the hub's rms_px)
  int views = 0;
  int marker = -1;                     // confirmed track's marker (0-based column), else -1
  uint64_t provisional_track = 0;      // tentative track's serial, 0 when none
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

class LiveReconstruction {
 public:
  // The rig must outlive this object. Throws std::invalid_argument on bad options.
  LiveReconstruction(const Rig& rig, double rate_hz, const ReconstructorOptions& recon = {},
                     std::vector<RigidBodyDefinition> bodies = {}, std::optional<MarkerSet> labels = {},
                     const BodyLiveFilterOptions& body_filter = {}, const TrackerOptions& tracker = {});

  // One assembled frame set; frame numbers must increase. now_ns() is read when the result is
  // complete. The returned frame stays valid until the next call.
  template <typename Clock>
  const LiveFrame& Process(const FrameSet& set, Clock now_ns) {
    Run(set);
    frame_.publish_ns = now_ns();
    return frame_;
  }
  const Tracker& tracker() const { return tracker_; }
  const Reconstructor& reconstructor() const { return reconstructor_; }

 private:
  void Run(const FrameSet& set);

  Reconstructor reconstructor_;
  Tracker tracker_;
  LiveBodyTracker bodies_;  // per-frame fits refined from past frames (body_live_filter.h)
  std::optional<MarkerLabeller> labeller_;
  std::vector<int64_t> tracks_;
  std::vector<ReconstructedPoint> points_;
  std::vector<Eigen::Vector3d> positions_;
  LiveFrame frame_;
};

}  // namespace mocap::service

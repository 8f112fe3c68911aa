// Every frame set's 3D result the moment it is assembled, shared by `serve` and `record`:
// reconstruction with the tracker's predictions, tracking, and one LiveFrame holding every
// point with whose it is. Nothing is held back: a point of a track not yet confirmed is
// published as provisional (under the id its track keeps when confirmed) in its own frame, a
// point no track took is published without an id; the confirmed samples (with the frames of a track
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
#include "pipeline/live_frame.h"
#include "recon/reconstructor.h"
#include "track/tracker.h"

namespace mocap::pipeline {

// A step after reconstruction, tracking, naming and rigid bodies, run on every frame before it is
// published (the live skeleton: live_skeleton.h, a library of its own so that the stream adapters
// linking this layer stay free of Ceres). Runs on the hub's loop: it must be quick.
class LiveStage {
 public:
  virtual ~LiveStage() = default;
  virtual void Run(LiveFrame* frame) = 0;
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
  // Runs `stage` on every frame from now on, after the stages added before it.
  void AddStage(std::unique_ptr<LiveStage> stage) { stages_.push_back(std::move(stage)); }
  const Tracker& tracker() const { return tracker_; }
  const Reconstructor& reconstructor() const { return reconstructor_; }

 private:
  void Run(const FrameSet& set);
  void FitBodies(uint64_t frame_number);

  Reconstructor reconstructor_;
  Tracker tracker_;
  LiveBodyTracker bodies_;  // per-frame fits refined from past frames (body_live_filter.h)
  std::optional<MarkerLabeller> labeller_;
  std::vector<int64_t> tracks_;
  std::vector<ReconstructedPoint> points_;
  std::vector<Eigen::Vector3d> positions_;
  LiveFrame frame_;
  std::vector<std::unique_ptr<LiveStage>> stages_;
};

}  // namespace mocap::pipeline

// Live reconstruction + tracking (see live_reconstruction.h).
#include "pipeline/live_reconstruction.h"

#include <algorithm>

namespace mocap::pipeline {
namespace {

TrackerOptions TrackerAt(double rate_hz, TrackerOptions options) {
  options.rate_hz = rate_hz;
  return options;
}

}  // namespace

LiveReconstruction::LiveReconstruction(const Rig& rig, double rate_hz, const ReconstructorOptions& recon,
                                       std::vector<RigidBodyDefinition> bodies, std::optional<MarkerSet> labels,
                                       const BodyLiveFilterOptions& body_filter, const TrackerOptions& tracker)
    : reconstructor_(rig, recon), tracker_(TrackerAt(rate_hz, tracker)), bodies_(std::move(bodies), {}, body_filter) {
  if (labels) {
    frame_.label_names = std::make_shared<const std::vector<std::string>>(labels->names);
    labeller_.emplace(std::move(*labels));
  }
}

void LiveReconstruction::Run(const FrameSet& set) {
  frame_.frame_number = set.frame_number;
  frame_.cameras = static_cast<int>(set.cameras.size());
  frame_.trigger_time_ns = 0;
  frame_.last_receive_ns = 0;
  for (const CameraFrame& camera : set.cameras) {
    if (camera.trigger_time_ns && (!frame_.trigger_time_ns || camera.trigger_time_ns < frame_.trigger_time_ns))
      frame_.trigger_time_ns = camera.trigger_time_ns;
    frame_.last_receive_ns = std::max(frame_.last_receive_ns, camera.receive_time_ns);
  }
  reconstructor_.Process(set, tracker_.Predict(set.frame_number), &points_);
  tracker_.FollowPointNoise(reconstructor_.point_noise_mm());
  frame_.samples.clear();
  tracker_.Update(set.frame_number, points_, &frame_.samples);
  const std::vector<PointIdentity>& identities = tracker_.point_identities();
  frame_.points.resize(points_.size());
  for (size_t i = 0; i < points_.size(); ++i) {
    LivePoint& out = frame_.points[i];
    out.position = points_[i].point_in_world;
    out.rms_px = points_[i].rms_px;
    out.views = points_[i].num_views;
    out.marker = identities[i].marker;
    out.id = identities[i].id;
    out.label = -1;
  }
  if (labeller_) {
    // Names follow the confirmed tracks (the tracker's marker numbers); a provisional point is
    // named only by its segment partners, for its own frame.
    positions_.resize(points_.size());
    tracks_.resize(points_.size());
    for (size_t i = 0; i < points_.size(); ++i) {
      positions_[i] = points_[i].point_in_world;
      tracks_[i] = identities[i].marker;
    }
    const std::vector<int>& labels = labeller_->Update(positions_, tracks_);
    for (size_t i = 0; i < points_.size(); ++i) frame_.points[i].label = labels[i];
  }
  if (!bodies_.bodies().empty()) FitBodies(set.frame_number);
  for (const std::unique_ptr<LiveStage>& stage : stages_) stage->Run(&frame_);
}

void LiveReconstruction::FitBodies(uint64_t frame_number) {
  positions_.resize(points_.size());
  for (size_t i = 0; i < points_.size(); ++i) positions_[i] = points_[i].point_in_world;
  const std::vector<BodyPose>& poses = bodies_.Update(frame_number, positions_);
  frame_.bodies.resize(poses.size());
  for (size_t b = 0; b < poses.size(); ++b) {
    LiveBody& out = frame_.bodies[b];
    out.id = static_cast<uint32_t>(b + 1);
    out.name = bodies_.bodies()[b].name;
    out.tracked = poses[b].tracked;
    out.predicted = poses[b].predicted;
    out.position = poses[b].pivot;
    out.orientation = poses[b].orientation;
    out.mean_error_mm = poses[b].mean_error_mm;
    out.markers = static_cast<int>(poses[b].markers);
  }
}

}  // namespace mocap::pipeline

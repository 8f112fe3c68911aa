// The live skeleton stage (see live_skeleton.h).
#include "pipeline/live_skeleton.h"

#include <chrono>
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <Eigen/Geometry>

#include "skeleton/skeleton_space.h"

namespace mocap::pipeline {

void LiveSkeletonOptions::Check() const {
  if (up_axis < -3 || up_axis > 2)
    throw std::invalid_argument("live skeleton: up_axis " + std::to_string(up_axis) +
                                " is not 0, 1, 2 (+x, +y, +z) or -1, -2, -3 (-x, -y, -z)");
  solve.Check();
}

Eigen::Matrix3d WorldFromSkeletonUp(int up_axis) {
  if (up_axis >= 0) return WorldFromSkeletonSpace(up_axis);
  // Upside down: half a turn about skeleton x first (y -> -y, z -> -z), then the positive axis's.
  return WorldFromSkeletonSpace(-up_axis - 1) * Eigen::Vector3d(1, -1, -1).asDiagonal();
}

std::shared_ptr<const LiveSkeletonModel> LiveSkeletonModelOf(const Skeleton& skeleton, const std::string& name) {
  auto model = std::make_shared<LiveSkeletonModel>();
  model->name = name;
  for (const SkeletonSegment& segment : skeleton.segments) {
    model->bones.push_back(segment.name);
    model->parents.push_back(segment.parent);
    model->offsets.push_back(segment.offset);
  }
  return model;
}

namespace {

Skeleton Checked(Skeleton skeleton) {
  skeleton.Check();
  return skeleton;
}

}  // namespace

LiveSkeletonStage::LiveSkeletonStage(Skeleton skeleton, const std::vector<std::string>& label_names,
                                     const LiveSkeletonOptions& options)
    : skeleton_(Checked(std::move(skeleton))), options_(options), solver_(skeleton_, options.solve) {
  options_.Check();
  world_from_skeleton_ = WorldFromSkeletonUp(options_.up_axis);
  skeleton_from_world_ = world_from_skeleton_.transpose();
  model_ = LiveSkeletonModelOf(skeleton_, options_.name);
  marker_of_label_.assign(label_names.size(), -1);
  for (size_t l = 0; l < label_names.size(); ++l) {
    marker_of_label_[l] = skeleton_.FindMarker(label_names[l]);
    if (marker_of_label_[l] >= 0) ++named_;
  }
  if (named_ < static_cast<size_t>(options_.solve.min_markers))
    throw std::invalid_argument("live skeleton '" + options_.name + "': the marker set names " + std::to_string(named_) +
                                " of the skeleton's " + std::to_string(skeleton_.markers.size()) +
                                " markers, fewer than the solve's minimum " + std::to_string(options_.solve.min_markers));
  observed_.assign(skeleton_.markers.size(), Eigen::Vector3d::Constant(NAN));
}

void LiveSkeletonStage::Run(LiveFrame* frame) {
  const auto start = std::chrono::steady_clock::now();
  std::fill(observed_.begin(), observed_.end(), Eigen::Vector3d::Constant(NAN));
  for (const LivePoint& point : frame->points) {
    if (point.label < 0 || static_cast<size_t>(point.label) >= marker_of_label_.size()) continue;
    const int m = marker_of_label_[static_cast<size_t>(point.label)];
    if (m >= 0) observed_[static_cast<size_t>(m)] = skeleton_from_world_ * point.position;
  }
  const SkeletonFrameFit fit = solver_.Solve(observed_);
  frame->skeletons.resize(1);
  LiveSkeleton& out = frame->skeletons[0];
  out.model = model_;
  out.markers = fit.markers;
  out.solved = fit.solved;
  out.rms_mm = fit.solved ? fit.rms_mm : 0.0;
  out.max_mm = fit.solved ? fit.max_mm : 0.0;
  out.bones.clear();
  if (!fit.solved) {
    out.state = fit.markers < options_.solve.min_markers ? "too few markers" : "not solved";
  } else {
    out.state = "solved";
    ForwardKinematics(skeleton_, fit.pose.data(), nullptr, &state_);
    out.bones.resize(skeleton_.segments.size());
    for (size_t s = 0; s < out.bones.size(); ++s) {
      out.bones[s].position = world_from_skeleton_ * state_.origin[s];
      out.bones[s].orientation = Eigen::Quaterniond(world_from_skeleton_ * state_.rotation[s]).normalized();
    }
  }
  out.solve_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace mocap::pipeline

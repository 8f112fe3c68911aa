// The live skeleton (`serve --skeleton SUBJECT.json --labels SET.json`): a LiveStage that fits a
// calibrated subject's skeleton (skeleton/skeleton_solver.h) to every frame's named points,
// warm-started from the last solved frame, and puts every segment's pose (world frame) and the
// fit's residuals into the frame (LiveFrame::skeletons). A frame with fewer of the skeleton's
// markers than the solve needs, or whose solve fails, carries no bones and says why; the next
// solved frame starts afresh. Markers of the skeleton that the marker set does not name are never
// seen; a marker set naming fewer of them than the solve's minimum is refused.
// In its own library (mocap_pipeline_skeleton: Ceres), not mocap_pipeline, which the stream
// adapters link. Errors: bad options and mismatched skeleton / marker set throw
// std::invalid_argument naming what.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "pipeline/live_frame.h"
#include "pipeline/live_reconstruction.h"
#include "skeleton/kinematics.h"
#include "skeleton/skeleton.h"
#include "skeleton/skeleton_solver.h"

namespace mocap::pipeline {

struct LiveSkeletonOptions {
  std::string name;                 // the subject's name in the frame (LiveSkeletonModel::name)
  int up_axis = 2;                  // the world's up axis: 0, 1, 2 for +x, +y, +z; -1, -2, -3 for -x, -y, -z
  // The solve's options; live, a warm-started frame's iterations are bounded lower than offline (a
  // warm start converges in 3-5; frames with misnamed markers would otherwise take up to 30 on
  // the loop); a fresh start keeps its 30.
  SkeletonSolveOptions solve = LiveSolveOptions();
  void Check() const;

  static SkeletonSolveOptions LiveSolveOptions() {
    SkeletonSolveOptions o;
    o.warm_iterations = 10;
    return o;
  }
};

// World from skeleton space (+y up) for a signed up axis (LiveSkeletonOptions::up_axis).
Eigen::Matrix3d WorldFromSkeletonUp(int up_axis);

// The names, tree and offsets of `skeleton` as every frame (and a stream's model description)
// shares them.
std::shared_ptr<const LiveSkeletonModel> LiveSkeletonModelOf(const Skeleton& skeleton, const std::string& name);

class LiveSkeletonStage : public LiveStage {
 public:
  // label_names: the marker set's names (LivePoint::label indexes them).
  LiveSkeletonStage(Skeleton skeleton, const std::vector<std::string>& label_names, const LiveSkeletonOptions& options);
  void Run(LiveFrame* frame) override;
  // Skeleton markers the marker set names (the others are never observed).
  size_t named_markers() const { return named_; }

 private:
  Skeleton skeleton_;
  LiveSkeletonOptions options_;
  Eigen::Matrix3d world_from_skeleton_;
  Eigen::Matrix3d skeleton_from_world_;
  std::shared_ptr<const LiveSkeletonModel> model_;
  std::vector<int> marker_of_label_;  // per marker-set name: the skeleton's marker, or -1
  size_t named_ = 0;
  SkeletonSolver solver_;
  std::vector<Eigen::Vector3d> observed_;
  SkeletonPoseState state_;
};

}  // namespace mocap::pipeline

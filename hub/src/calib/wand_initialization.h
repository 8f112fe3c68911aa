// Initial camera poses from wand frames, before bundle adjustment: the reference camera is the
// one that saw the wand most often (seed 004's rule); cameras join one at a time through the
// posed camera they share most frames with, by an essential matrix whose scale comes from the
// wand length. The world frame is the reference camera's frame.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "calib/wand_observations.h"
#include "geometry/camera.h"

namespace mocap {

struct WandInitializationOptions {
  int min_pair_frames = 30;         // shared wand frames for a camera pair to be tried
  int max_frames_per_pair = 400;    // evenly subsampled: plenty for five unknowns, keeps RANSAC fast
  double ransac_threshold_px = 2.0;
  double ransac_confidence = 0.999;
  int ransac_max_iterations = 2000;
  // Relative median absolute deviation of the wand lengths triangulated by one pair above which
  // the pair's pose is not trusted.
  double max_length_spread = 0.08;
  int reference_camera = -1;  // rig index; -1 picks the camera with the most wand views

  void Check() const;
};

// cam2_from_cam1 with metric translation (mm).
struct RelativePose {
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();
  int inlier_frames = 0;
  double length_spread = 0.0;
};

// Essential matrix between two cameras from frames both saw. The wand's end markers are not yet
// labelled, so both pairings enter RANSAC and each frame keeps the one the model explains.
// Returns false with the reason in *why.
bool EstimateWandRelativePose(const std::vector<std::pair<const WandView*, const WandView*>>& views,
                              const WandGeometry& wand, double focal_px,
                              const WandInitializationOptions& options, RelativePose* cam2_from_cam1,
                              std::string* why);

struct WandInitialization {
  size_t reference_camera = 0;
  std::vector<Camera> cameras;      // intrinsics from the rig; poses valid where posed[i]
  std::vector<bool> posed;
  std::vector<std::string> unposed_reason;  // empty where posed
  std::vector<size_t> views_per_camera;
};

// Throws std::runtime_error when not even the reference camera can be paired with another.
WandInitialization InitializeWandPoses(const std::vector<WandFrame>& frames, const Rig& rig,
                                       const WandGeometry& wand, const WandInitializationOptions& options);

}  // namespace mocap

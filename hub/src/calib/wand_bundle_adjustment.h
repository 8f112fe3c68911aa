// Bundle adjustment of cameras and wand poses with Ceres: every marker view is a reprojection
// residual under a robust loss; the wand length is built into the wand's parametrisation, which
// fixes the scale; the reference camera's pose is held to fix the rigid gauge.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "calib/wand_observations.h"
#include "geometry/camera.h"

namespace mocap {

enum class IntrinsicsRefinement { kNone, kFocalAndPrincipal, kAll };
const char* IntrinsicsRefinementName(IntrinsicsRefinement refinement);
// Throws std::invalid_argument listing the valid names.
IntrinsicsRefinement IntrinsicsRefinementFromName(const std::string& name);

// A wand pose: the midpoint of its end markers and the unit axis from first to last marker.
struct WandPose {
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  Eigen::Vector3d axis = Eigen::Vector3d::UnitX();

  Eigen::Vector3d Marker(const WandGeometry& wand, size_t k) const {
    return centre + wand.marker_offsets_mm[k] * axis;
  }
};

struct WandBundleOptions {
  IntrinsicsRefinement refine_intrinsics = IntrinsicsRefinement::kNone;
  double loss_scale_px = 1.0;  // Huber: quadratic below, linear above
  int max_iterations = 100;
  int num_threads = 1;
  size_t fixed_camera = 0;  // rig index whose pose defines the world frame

  void Check() const;
};

struct WandBundleSummary {
  bool usable = false;  // Ceres reached a solution (converged or ran out of iterations)
  int iterations = 0;
  double initial_cost = 0.0;
  double final_cost = 0.0;
  std::string message;
};

// Refines cameras[i] (pose, and intrinsics if asked) for active[i], and every wand pose.
// frames[f] is seen at wand_poses[f]; views of inactive cameras are ignored.
WandBundleSummary AdjustWandBundle(const std::vector<WandFrame>& frames, const WandGeometry& wand,
                                   const WandBundleOptions& options, const std::vector<bool>& active,
                                   std::vector<Camera>* cameras, std::vector<WandPose>* wand_poses);

}  // namespace mocap

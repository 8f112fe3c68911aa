// Multi-view triangulation of one marker from undistorted observations: the shared core
// (geometry/triangulation.h: linear estimate, then Gauss-Newton on the reprojection error in
// pixels), then residual checks that drop one outlier view at a time while three or more remain.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "recon/frame_views.h"
#include "recon/recon_options.h"

namespace mocap {

struct TriangulatedPoint {
  Eigen::Vector3d point_in_world = Eigen::Vector3d::Zero();
  std::vector<int> observations;  // indices into FrameViews::observations, the views kept
  std::vector<int> rejected;      // views dropped as outliers
  double rms_px = 0.0;
  double max_px = 0.0;
};

// Linear estimate; false when the views are degenerate (parallel rays, fewer than 2 views).
bool TriangulateLinear(const RigModel& rig, const FrameViews& views,
                       const std::vector<int>& observations, Eigen::Vector3d* point_in_world);

// Gauss-Newton refinement of reprojection error (px), in place; returns false when a view ends
// behind its camera or the solve breaks down.
bool RefinePoint(const RigModel& rig, const FrameViews& views, const std::vector<int>& observations,
                 int iterations, Eigen::Vector3d* point_in_world);

// Per-view reprojection errors in px, same order as `observations`.
void ReprojectionErrors(const RigModel& rig, const FrameViews& views,
                        const std::vector<int>& observations, const Eigen::Vector3d& point_in_world,
                        std::vector<double>* errors_px);

// The residual (px) under which a median error may still belong to a precise point once one
// biased view is out: 25 % over the precise limit (precise_fraction of max_reprojection_px). The
// cheap gates in front of the coincident-view tests use it.
inline double PreciseGatePx(const TriangulationOptions& options) {
  return 1.25 * options.precise_fraction * options.max_reprojection_px;
}

// The full pipeline with outlier rejection. False when fewer than options.min_views consistent
// views remain. Views flagged merged, and those `shared` marks (one entry per observation, may
// be null: blobs two markers share), are left out of the solve while min_views others remain.
// Reentrant (per-thread scratch).
bool TriangulateRobust(const RigModel& rig, const FrameViews& views, const std::vector<int>& observations,
                       const TriangulationOptions& options, TriangulatedPoint* result,
                       const std::vector<char>* shared = nullptr);

}  // namespace mocap

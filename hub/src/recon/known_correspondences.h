// The known-correspondence floor: every true marker triangulated from its own blobs, found by
// projecting its true position into each camera. What a reconstruction that knew every
// correspondence would give; `bench` times against it and `reconstruct --known-correspondences`
// writes it, so `eval` can compare a reconstruction's accuracy with it. Simulation and evaluation
// only: it needs the true positions.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "recon/frame_views.h"
#include "recon/recon_options.h"
#include "recon/triangulation.h"

namespace mocap {

struct KnownCorrespondenceOptions {
  // A blob is a marker's own view when its undistorted position lies this close to the marker's
  // true projection (pixels at the camera's focal length).
  double max_px = 3.0;
  // Blobs flagged merged are left out: their centroid lies between two markers and measures
  // neither, so the floor is what the unmerged views allow.
  bool skip_merged = true;
};

// Per marker, the observations (indices into views.observations) that are its own image, the
// nearest within the limit in each camera. NaN positions (absent markers) get no views.
void FindTrueViews(const RigModel& rig, const FrameViews& views, const std::vector<Eigen::Vector3d>& truth,
                   const KnownCorrespondenceOptions& options, std::vector<std::vector<int>>* views_of_marker);

// Triangulates each marker from its true views (TriangulateRobust, two views at least); a marker
// that cannot be triangulated gets a NaN position. Returns how many were triangulated.
size_t TriangulateKnownCorrespondences(const RigModel& rig, const FrameViews& views,
                                       const std::vector<std::vector<int>>& views_of_marker,
                                       const TriangulationOptions& options,
                                       std::vector<Eigen::Vector3d>* positions);

}  // namespace mocap

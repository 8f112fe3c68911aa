// The world frame the user chose: found from an L-frame (3-4 markers of known, asymmetric
// geometry laid where the origin should be) by Kabsch (seed 003), or levelled on floor points.
// A wand calibration's world is its reference camera; these move it without changing the cameras
// relative to each other.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "geometry/rigid_fit.h"
#include "geometry/camera.h"
#include "ingest/camera_frame.h"

namespace mocap {

// A 4-marker L lying on the floor: origin, two markers along the first horizontal axis (200 and
// 500 mm) and one along the second (350 mm); all pairwise distances differ, so every marker is
// recognisable. up_axis 2 (z up): arms along +x and +y; 1 (y up): along +z and +x; 0 (x up):
// along +y and +z (first arm x second arm = up in each case).
std::vector<Eigen::Vector3d> DefaultLFrame(int up_axis);

struct LFrameOptions {
  // A candidate assignment of reconstructed points to the model is accepted when the rigid fit
  // leaves at most this RMS, mm.
  double max_fit_rms_mm = 6.0;
  int min_frames = 3;  // frames in which the whole L-frame must be found

  void Check() const;
};

struct WorldFrameFit {
  SimilarityTransform new_from_old;  // rigid: scale 1
  int frames_used = 0;
  double fit_rms_mm = 0.0;                   // of the averaged markers against the model
  std::vector<Eigen::Vector3d> measured;     // averaged marker positions, old world
};

// Throws std::invalid_argument for an unusable model (fewer than 3 markers, collinear, or
// markers that cannot be told apart) and std::runtime_error, with what to do, when the L-frame
// is not found in enough frames.
WorldFrameFit LocateLFrame(const std::vector<FrameSet>& frames, const Rig& rig,
                           const std::vector<Eigen::Vector3d>& model, const LFrameOptions& options);

// Picks, among reconstructed points, the ones matching the model (any order, extra points
// allowed). Returns false when no assignment fits within max_fit_rms_mm; else matched[k] is the
// point of model marker k.
bool MatchModel(const std::vector<Eigen::Vector3d>& points, const std::vector<Eigen::Vector3d>& model,
                double max_fit_rms_mm, std::vector<Eigen::Vector3d>* matched);

// Levels the world on points lying on the floor: the plane through them becomes up = 0 with
// +up towards the cameras, the origin moves to the points' centroid, the horizontal heading is
// kept as far as possible. Throws std::invalid_argument for fewer than 3 or collinear points.
WorldFrameFit LevelOnFloor(const std::vector<Eigen::Vector3d>& floor_points, const Rig& rig, int up_axis);

// The same cameras described in the new world frame.
Rig TransformRig(const Rig& rig, const SimilarityTransform& new_from_old);

}  // namespace mocap

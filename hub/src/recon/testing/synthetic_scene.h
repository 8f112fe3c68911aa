// Self-made synthetic data for recon/track tests and the bench: a ring rig, markers on rigid
// bodies moving smoothly, and their projection into blobs with noise, occlusions lasting several
// frames, spurious blobs (static and flickering) and dropped camera frames. Not the simulator
// (sim layer, above recon): a small independent generator so these layers test themselves.
#pragma once

#include <cstdint>
#include <random>
#include <vector>

#include <Eigen/Core>

#include "geometry/camera.h"
#include "ingest/camera_frame.h"

namespace mocap::testing {

// num_cameras cameras on a circle of `radius_mm` at `height_mm` (z up), all aimed at `target`.
Rig MakeRingRig(int num_cameras, double radius_mm, double height_mm, const Eigen::Vector3d& target,
                double fx = 1100.0, int width = 1280, int height = 800,
                const std::array<double, 5>& distortion = {0.0, 0.0, 0.0, 0.0, 0.0});

// Markers in groups of `markers_per_body` fixed on rigid bodies that translate along smooth
// paths and turn, inside a ~1.6 m cube around the origin (z up, 0..1.8 m).
class SyntheticMotion {
 public:
  SyntheticMotion(int num_markers, int markers_per_body, uint32_t seed);
  int NumMarkers() const { return static_cast<int>(offsets_.size()); }
  std::vector<Eigen::Vector3d> At(double time_s) const;

 private:
  struct Body {
    Eigen::Vector3d center, amplitude, frequency, phase;
    double spin_rate, tilt;
  };
  std::vector<Body> bodies_;
  std::vector<int> body_of_marker_;
  std::vector<Eigen::Vector3d> offsets_;
};

struct ProjectionFaults {
  double noise_px = 0.0;
  double occlusion = 0.0;        // chance per frame that a visible marker starts an occlusion
  int occlusion_frames = 5;      // mean occlusion length in frames
  int spurious = 0;              // false blobs per camera per frame (half static, half flicker)
  double drop_frames = 0.0;      // chance that a camera's frame is lost
};

// Which marker made each blob: truth[camera_index][blob] = marker index, or -1 for spurious.
using BlobTruth = std::vector<std::vector<int>>;

class FrameProjector {
 public:
  FrameProjector(const Rig& rig, const ProjectionFaults& faults, uint32_t seed);
  // Projects markers into every camera; frame sets list cameras in rig order.
  void Project(uint64_t frame_number, const std::vector<Eigen::Vector3d>& markers,
               FrameSet* frame_set, BlobTruth* truth);

 private:
  const Rig& rig_;
  ProjectionFaults faults_;
  std::mt19937 rng_;
  std::vector<std::vector<uint64_t>> occluded_until_;  // [camera][marker] frame number
  std::vector<std::vector<Eigen::Vector2d>> static_spurious_;
};

}  // namespace mocap::testing

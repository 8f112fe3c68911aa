// Scenes for the tests of the layers above (recon, track, calib) and the bench, built from the
// simulator's own parts: cameras aimed with AimCamera, blobs from the FaultyProjector. Fixed,
// seeded geometry that a test can reason about (z up): a ring of cameras at given radius and
// heights, markers on rigid bodies (what the tracker's rigid model needs), wand poses.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "geometry/camera.h"
#include "ingest/camera_frame.h"
#include "io/marker_trajectories.h"
#include "simcore/projector.h"

namespace mocap::testing {

// SHARED_DIR/data/motions/walk.trc when it exists (the real walk: 41 markers, 151 frames at
// 60 Hz), otherwise a synthetic walker of the same size.
MarkerTrajectories WalkOrSyntheticWalker(const std::string& shared_dir);

// num_cameras cameras on a circle of `radius_mm`, alternately at height_mm and 0.65 height_mm
// (z up), all aimed at `target`; ids 1..n.
Rig MakeRingRig(int num_cameras, double radius_mm, double height_mm, const Eigen::Vector3d& target,
                double fx = 1100.0, int width = 1280, int height = 800,
                const std::array<double, 5>& distortion = {0.0, 0.0, 0.0, 0.0, 0.0});

// Camera at centre_in_world looking at target_in_world (z up), 1280x800, f = 900 px, no distortion.
Camera LookAtCamera(uint32_t id, const Eigen::Vector3d& centre_in_world, const Eigen::Vector3d& target_in_world);

// n cameras on a circle (radius 4 m, heights alternating 2.2 / 2.8 m) aimed near (0, 0, 1 m),
// 1280x800, f = 900 px, barrel distortion, seeded jitter.
Rig RingRig(int n, uint32_t seed);

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

// Which marker made each blob: truth[camera_index][blob] = marker index, or -1 for spurious;
// an empty row for a camera whose frame was dropped.
using BlobTruth = std::vector<std::vector<int>>;

// The simulator's FaultyProjector on a test's terms: whole frame sets, cameras in rig order,
// which marker made each blob. Markers do not merge (tests of merged blobs use the simulator).
class FrameProjector {
 public:
  FrameProjector(const Rig& rig, const ProjectionFaults& faults, uint32_t seed);
  void Project(uint64_t frame_number, const std::vector<Eigen::Vector3d>& markers, FrameSet* frame_set,
               BlobTruth* truth);

 private:
  const Rig& rig_;
  ProjectOptions options_;
  std::unique_ptr<FaultyProjector> projector_;  // made for the first frame's marker count
  std::vector<int> seeing_;
  std::vector<std::vector<int>> blob_markers_;
};

struct WandScene {
  std::vector<FrameSet> frames;
  std::vector<Eigen::Vector3d> wand_centres;  // truth, per frame
};

// Random wand poses in a 3 x 3 x 1.8 m box (markers at marker_offsets_mm along the wand from its
// centre); markers outside an image or behind a camera are not seen; blob order within a camera
// frame is random.
WandScene MakeWandScene(const Rig& rig, const std::vector<double>& marker_offsets_mm, int frames, double noise_px,
                        uint32_t seed);

}  // namespace mocap::testing

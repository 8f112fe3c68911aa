// Turns 3D marker positions into what each camera would report: 2D blobs with the faults of a
// real system (centroid noise, lasting occlusion, merged blobs, static and flickering false
// blobs, dropped frames). Seeded per camera, so a failing case replays exactly.
#pragma once

#include <cstdint>
#include <random>
#include <vector>

#include "geometry/camera.h"
#include "ingest/camera_frame.h"

namespace mocap {

struct ProjectOptions {
  double noise_px = 0.0;          // centroid noise sigma per axis
  double occlusion = 0.0;         // probability a marker is hidden from one camera at a frame
  double occlusion_frames = 5.0;  // mean length of one occlusion, frames
  double spurious = 0.0;          // false blobs per camera per frame (half static, half flicker)
  // Blobs closer than this merge into one at their (area-weighted) mean. Negative = realistic:
  // two blobs merge when they touch, i.e. centres closer than the sum of their radii.
  double merge_px = -1.0;
  double drop_frames = 0.0;       // probability that a camera's whole frame is lost
  // Probability that a camera frame's datagrams reach the hub late, after those of the next
  // late_frames frames (network queueing); the session log keeps arrival order. Applied by
  // ProjectSession, not by the projector.
  double late = 0.0;
  int late_frames = 3;
  double marker_diameter_mm = 14.0;
  // A merged blob is flagged (kBlobMerged) when its shape is less round than this, as the node's
  // detector decides (firmware detect: merged_roundness, sqrt(minor / major) of its moments).
  double merged_roundness = 0.7;
  uint64_t seed = 1;

  // Throws std::invalid_argument naming the bad option.
  void Check() const;
};

class FaultyProjector {
 public:
  FaultyProjector(const Rig& rig, size_t num_markers, const ProjectOptions& options);

  // One frame: `points` holds num_markers positions (NaN = marker absent). Returns the frames of
  // the cameras that did not drop this frame, blobs in scanline order. cameras_seeing (resized
  // to num_markers) counts, per marker, the cameras in which it makes (part of) a blob.
  // blob_markers (optional) gets, per returned frame and blob, the marker that made it (the
  // first of a merged blob's markers) or -1 for a false blob: what tests need to hide a marker.
  std::vector<CameraFrame> Project(uint64_t frame_number, uint64_t trigger_time_ns,
                                   const Eigen::Vector3d* points, std::vector<int>* cameras_seeing,
                                   std::vector<std::vector<int>>* blob_markers = nullptr);
  // The same with each camera's own positions (camera_points[i] for rig camera i, num_markers
  // each): free-running cameras expose at their own instants. The faults' draws are those of the
  // call above.
  std::vector<CameraFrame> Project(uint64_t frame_number, uint64_t trigger_time_ns,
                                   const std::vector<const Eigen::Vector3d*>& camera_points,
                                   std::vector<int>* cameras_seeing,
                                   std::vector<std::vector<int>>* blob_markers = nullptr);

  // Radius in pixels of a marker's blob at this depth in front of the camera.
  double BlobRadiusPx(const Camera& camera, double depth_mm) const;

  // One marker's image in one camera, before merging and centroid noise.
  struct MarkerImage {
    Eigen::Vector2d pixel;  // distorted pixel position of the marker's centre
    double radius = 0.0;    // blob radius, px
    double depth = 0.0;     // mm in front of the camera
    size_t marker = 0;
  };

  // Advances camera `index`'s occlusion chains by one frame and returns the markers it images:
  // present, not occluded, in front, inside the image and the lens model's range. Project()
  // turns them into blobs; `sim render` draws them as spots. Call once per camera and frame.
  std::vector<MarkerImage> ImageMarkers(size_t index, const Eigen::Vector3d* points);

  // Brightness above the background at the centre of a marker's image at this depth, grey
  // levels: retro-reflector return falls with the square of distance (ring light at the lens).
  static double MarkerPeak(double depth_mm);

 private:
  struct CameraState {
    std::mt19937_64 rng;
    std::vector<char> occluded;
    std::vector<Eigen::Vector2d> static_spots;
    // Normalized radius beyond which the radial lens model folds back (no real lens images it).
    double valid_radius = 0.0;
  };

  // The random draws of one camera frame, in the order the stages below make them.
  struct Draws {
    std::uniform_real_distribution<double> unit{0.0, 1.0};
    std::normal_distribution<double> gauss{0.0, 1.0};
  };
  // False when the camera drops this frame.
  bool ProjectCamera(size_t index, uint64_t frame_number, const Eigen::Vector3d* points,
                     std::vector<int>* cameras_seeing, CameraFrame* frame, std::vector<int>* blob_markers);
  // Union-find parents of the spots that overlap (merge into one blob).
  std::vector<int> MergeOverlapping(const std::vector<MarkerImage>& spots) const;
  // A blob's centroid as the node measures it: with centroid noise, kept on the sensor.
  Eigen::Vector2d MeasuredPixel(size_t index, Eigen::Vector2d pixel, Draws* draws);
  // parent: MergeOverlapping's (its paths are compressed while grouping).
  void AddMarkerBlobs(size_t index, const std::vector<MarkerImage>& spots, std::vector<int> parent,
                      Draws* draws, CameraFrame* frame, std::vector<int>* blob_markers);
  // Static reflections and one-frame flicker.
  void AddSpuriousBlobs(size_t index, Draws* draws, CameraFrame* frame, std::vector<int>* blob_markers);
  static void SortInScanlineOrder(CameraFrame* frame, std::vector<int>* blob_markers);

  const Rig& rig_;
  size_t num_markers_;
  ProjectOptions options_;
  double occlusion_start_ = 0.0;  // per-frame probability a visible marker becomes occluded
  double occlusion_end_ = 1.0;    // per-frame probability an occlusion ends
  std::vector<CameraState> states_;
};

}  // namespace mocap

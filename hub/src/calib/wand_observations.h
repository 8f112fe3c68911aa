// Picks the frames in which a camera sees exactly the wand: its markers and nothing else, after
// masking static reflections. Everything downstream (initial poses, bundle adjustment) works on
// these per-camera views of one wand pose.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "geometry/camera.h"
#include "ingest/camera_frame.h"

namespace mocap {

// Markers along a straight wand, as signed offsets in mm from the midpoint of the two end
// markers. Two markers: {-L/2, +L/2}; a third lies between them, off-centre so that the ends
// can be told apart.
struct WandGeometry {
  std::vector<double> marker_offsets_mm;

  static WandGeometry TwoMarker(double length_mm);
  // One marker waved alone (single_marker_calibration.h): a view is a camera frame with exactly
  // one blob.
  static WandGeometry SingleMarker();
  // middle_from_first_mm: distance of the middle marker from the first end marker.
  static WandGeometry ThreeMarker(double length_mm, double middle_from_first_mm);
  double LengthMm() const { return marker_offsets_mm.back() - marker_offsets_mm.front(); }
  size_t MarkerCount() const { return marker_offsets_mm.size(); }
  // Throws std::invalid_argument with the reason when the geometry is unusable.
  void Check() const;
};

struct WandSelectionOptions {
  // Blobs seen at the same place in at least this fraction of a camera's frames are static
  // reflections and are removed before counting (the wand never rests that long).
  double static_min_fraction = 0.2;
  double static_radius_px = 2.0;
  // Two wand blobs closer than this in one image may be merged or swapped: the view is skipped.
  double min_blob_separation_px = 6.0;
  // A three-marker view whose middle blob strays further than this fraction of the end-to-end
  // image distance from the line between the ends is not the wand.
  double max_middle_offset_fraction = 0.08;
  // Frames seen by fewer cameras carry no geometry.
  int min_views_per_frame = 2;

  void Check() const;
};

// One camera's view of the wand. Pixels are ordered along the wand; for the two end markers the
// order is only known up to a swap until the frame is labelled across cameras.
struct WandView {
  size_t camera = 0;                       // index into the rig's cameras
  std::vector<Eigen::Vector2d> pixels;     // distorted, px
  std::vector<Eigen::Vector2d> normalized; // undistorted normalized coordinates

  void SwapEnds();
};

struct WandFrame {
  uint64_t frame_number = 0;
  std::vector<WandView> views;
};

struct WandSelectionStats {
  size_t frames_in = 0;
  size_t frames_selected = 0;
  std::vector<size_t> static_blobs_masked;  // per camera, blobs removed as static reflections
  std::vector<size_t> views_selected;       // per camera
};

// Cameras are matched to frames by id; blobs from cameras not in the rig are ignored. The rig's
// intrinsics are used to undistort.
std::vector<WandFrame> SelectWandFrames(const std::vector<FrameSet>& frames, const Rig& rig,
                                        const WandGeometry& wand, const WandSelectionOptions& options,
                                        WandSelectionStats* stats);

}  // namespace mocap

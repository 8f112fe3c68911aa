// Live wanding feedback: per camera, how often it saw exactly the wand and where in its image
// (a grid of cells with counts), the share of the image covered, and what the operator should do
// next ("wave towards the top left"). Fed one frame set at a time while the wand is waved; the
// solve itself later runs on the recorded session (wand_calibration.h).
//
// Threads: none (the owner feeds it from one thread). Error policy: Check() throws
// std::invalid_argument; frame sets from outside never throw (cameras not in the rig and
// out-of-image blobs are ignored).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "geometry/camera.h"
#include "ingest/camera_frame.h"

namespace mocap {

struct WandCoverageOptions {
  int columns = 8;  // grid over each image
  int rows = 6;
  // A cell is covered once the wand's markers were seen in it this many times.
  int cell_samples = 4;
  // A camera frame counts as a wand sample when it holds exactly the wand's blobs, this far apart
  // at least (closer blobs may be merged or swapped), and another camera of the same frame set
  // sees the wand too (one view carries no geometry).
  double min_blob_separation_px = 6.0;
  int min_views_per_frame = 2;

  // Throws std::invalid_argument naming the bad option.
  void Check() const;
};

// One camera's tally.
struct CameraCoverage {
  uint32_t id = 0;
  int width = 0;
  int height = 0;
  size_t samples = 0;             // frames in which it saw exactly the wand
  std::vector<uint32_t> counts;   // columns x rows, row-major from the top left: marker sightings

  // Fraction of the cells with at least cell_samples sightings.
  double Share(int cell_samples) const;
};

// What to do next for one camera, in the operator's words.
struct CoverageAdvice {
  bool enough = false;  // samples and coverage both reached
  std::string region;   // the emptiest region: "top left", "top", ..., "centre"; empty if enough
  std::string text;     // "camera 4: wave towards the top left (coverage 31 % of 40 %, 120/300 samples)"
};

class WandCoverage {
 public:
  // wand_markers: 2 or 3 (1: a single marker waved). Throws std::invalid_argument on bad options.
  WandCoverage(const Rig& rig, size_t wand_markers, const WandCoverageOptions& options);

  // One frame set; returns whether it counted as a wand frame (enough cameras saw the wand).
  bool Add(const FrameSet& set);

  const std::vector<CameraCoverage>& cameras() const { return cameras_; }
  const WandCoverageOptions& options() const { return options_; }
  size_t frame_sets() const { return frame_sets_; }
  size_t wand_frames() const { return wand_frames_; }

  // Advice for camera `index` against the targets: min_samples wand samples and a covered share
  // of at least coverage_target.
  CoverageAdvice Advise(size_t index, size_t min_samples, double coverage_target) const;

 private:
  bool IsWandView(const CameraFrame& frame, size_t camera) const;

  WandCoverageOptions options_;
  size_t markers_;
  std::vector<CameraCoverage> cameras_;
  size_t frame_sets_ = 0;
  size_t wand_frames_ = 0;
};

// The name of the 3 x 3 image region of cell (column, row) of a columns x rows grid:
// "top left", "top", "top right", "left", "centre", "right", "bottom left", "bottom", "bottom right".
std::string ImageRegionName(int column, int row, int columns, int rows);

}  // namespace mocap

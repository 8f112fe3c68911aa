// Wand calibration of a whole rig, end to end: select wand frames, initial poses, label the
// wand ends across cameras, robust bundle adjustment with outlier rejection, then a per-camera
// quality report that accepts a camera or refuses it with the reason and what to do.
// Error policy of the calib layer: options that fail Check() throw std::invalid_argument; data
// that cannot be calibrated at all throws std::runtime_error with a one-line reason; a camera
// that cannot be calibrated is not an exception but a refusal in the report.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "calib/wand_bundle_adjustment.h"
#include "calib/wand_initialization.h"
#include "calib/wand_observations.h"
#include "geometry/camera.h"
#include "ingest/camera_frame.h"

namespace mocap {

struct WandCalibrationOptions {
  WandSelectionOptions selection;
  WandInitializationOptions initialization;
  WandBundleOptions bundle;  // fixed_camera is set to the reference camera
  // Views whose reprojection error exceeds max(outlier_min_px, outlier_sigmas * robust sigma)
  // are dropped between bundle passes.
  double outlier_min_px = 1.0;
  double outlier_sigmas = 5.0;
  double initial_gate_px = 25.0;  // before the first bundle, poses are only roughly right
  int refinement_passes = 3;      // bundle passes, each followed by outlier rejection
  int early_pass_iterations = 15;  // solver iterations of every pass but the last
  // Acceptance of a camera.
  int min_views_per_camera = 100;
  double min_coverage = 0.2;       // fraction of coverage_grid x coverage_grid image cells
  int coverage_grid = 8;
  double max_camera_rms_px = 1.4;
  // A camera whose residual is this many times the median camera's, or which keeps fewer than
  // this fraction of its wand views through outlier rejection, disagrees with the rest of the
  // rig (wrong intrinsics, moved during the recording) even if its own numbers look small.
  double max_rms_ratio = 2.5;
  double min_inlier_fraction = 0.6;

  void Check() const;
};

struct LengthErrorStats {
  size_t count = 0;
  double mean_mm = 0.0;  // signed: triangulated minus true length
  double rms_mm = 0.0;
  double median_abs_mm = 0.0;
  double p95_abs_mm = 0.0;
  double max_abs_mm = 0.0;
};

struct CameraCalibrationReport {
  uint32_t id = 0;
  bool accepted = false;
  std::string reason;  // why refused and what to do; empty when accepted
  size_t views_selected = 0;
  size_t views_used = 0;
  double reprojection_rms_px = 0.0;
  double coverage = 0.0;
  LengthErrorStats wand_length;  // frames this camera took part in
};

// The raw figures behind the report's plots (wand_report.h), from the final evaluation.
struct WandCalibrationFigures {
  int coverage_grid = 0;                             // cells per side
  std::vector<std::vector<uint32_t>> coverage;       // per camera (rig order): sightings per cell, row-major
  std::vector<std::vector<float>> residuals_px;      // per camera: reprojection error length per observation
  std::vector<double> wand_length_errors_mm;         // per used frame, signed
  std::vector<Eigen::Vector3d> wand_centres;         // solved wand centres (at most 2000, evenly spread)
};

struct WandCalibrationResult {
  Rig rig;  // accepted cameras; world frame = reference camera's frame
  uint32_t reference_camera_id = 0;
  std::vector<CameraCalibrationReport> cameras;  // every input camera, in rig order
  LengthErrorStats wand_length;                  // independent triangulation, all used frames
  double reprojection_rms_px = 0.0;
  // Observations left out of the RMS because the solved marker lies behind the camera.
  size_t unprojected_observations = 0;
  size_t frames_in = 0;
  size_t frames_selected = 0;
  size_t frames_used = 0;
  int solver_iterations = 0;
  std::string solver_message;
  // Wall-clock seconds per stage, for the report and the benchmark.
  double select_seconds = 0.0;
  double initialize_seconds = 0.0;
  double bundle_seconds = 0.0;
  WandCalibrationFigures figures;

  bool AllAccepted() const;
};

// `intrinsics` gives each camera's id, image size and lens; its poses are ignored.
WandCalibrationResult CalibrateWand(const std::vector<FrameSet>& frames, const Rig& intrinsics,
                                    const WandGeometry& wand, const WandCalibrationOptions& options);

// Length error statistics of a set of signed errors (mm).
LengthErrorStats SummarizeLengthErrors(std::vector<double> errors_mm);

}  // namespace mocap

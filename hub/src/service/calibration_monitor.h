// Continuous calibration in `serve`: watches every camera's reprojection residuals in the live
// reconstruction and re-solves a camera that moved. Each published frame set's points (with the
// live reconstructor's views, no second reconstruction) go into a sliding window of marker
// samples (calib/marker_residuals.h); every check_every_s the window is judged
// (calib/bump_detector.h) and, when a camera is bumped or drifting, re-solved with the other
// cameras held (calib/extrinsic_refinement.h). Judging and solving run on one worker thread on a
// snapshot of the window (shared immutable per-frame chunks: the loop copies pointers only), so
// the loop only collects; their result is picked up on a later frame.
// A camera's state change is logged (warning for drifting, bumped and refused solves), and
// StatusJson() gives the figures, the state and the last solve per camera for the status API.
// The live reconstruction keeps its calibration: a solved pose is reported (and offered as the
// calibration to write with `calibrate refine` or to restart with), not swapped in mid-capture.
//
// Threads: Add() and StatusJson() on the service loop only. Error policy: options Check()
// throws std::invalid_argument; a failed solve is a logged, reported state, never an exception.
#pragma once

#include <cstdint>
#include <deque>
#include <future>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "calib/extrinsic_refinement.h"
#include "calib/marker_residuals.h"
#include "geometry/camera.h"
#include "recon/reconstructor.h"

namespace mocap::service {

struct CalibrationMonitorOptions {
  double window_s = 2.0;       // the samples judged: this much of the latest capture
  double check_every_s = 0.5;  // how often the window is judged
  double resolve_every_s = 10.0; // a moved camera is solved again at most this often
  int frames_per_window = 120; // frame sets sampled per window (every Nth at high rates)
  bool refine = true;          // re-solve a moved camera (else only report it)
  MarkerResidualOptions residuals;
  ExtrinsicRefinementOptions refinement;

  void Check() const;
};

class CalibrationMonitor {
 public:
  // The rig must outlive the monitor. Throws std::invalid_argument on bad options.
  CalibrationMonitor(const Rig& rig, double rate_hz, const CalibrationMonitorOptions& options);
  ~CalibrationMonitor();

  // `set` as `reconstructor` (the live one, same rig) has just reconstructed it.
  void Add(const FrameSet& set, const Reconstructor& reconstructor);
  // Waits for a check in flight and takes its result (tests and shutdown).
  void Finish();

  nlohmann::json StatusJson() const;
  CameraPoseState state(size_t camera_index) const { return cameras_[camera_index].state; }
  // The latest accepted pose of a camera, if one was solved.
  const std::optional<Camera>& solved_pose(size_t camera_index) const { return cameras_[camera_index].solved; }
  uint64_t checks() const { return checks_; }

 private:
  struct CameraStatus {
    CameraPoseState state = CameraPoseState::kUnknown;
    CameraResiduals residuals;
    uint64_t since_frame = 0;         // frame of the check that set the state
    std::optional<Camera> solved;     // accepted pose of the last solve
    double centre_change_mm = 0.0;
    double rotation_change_deg = 0.0;
    double residual_after_px = 0.0;
    std::string note;                 // why the last solve was refused
    uint64_t solved_frame = 0;
  };
  struct CheckResult {
    uint64_t frame = 0;
    BumpDetection detection;
    std::optional<ExtrinsicRefinement> refinement;
    std::string error;
  };

  void StartCheck(uint64_t frame);
  void TakeResult(CheckResult result);

  const Rig& rig_;
  CalibrationMonitorOptions options_;
  MarkerResidualCollector collector_;  // turns each frame set into samples, kept in window_
  struct Chunk {  // one frame set's samples and blobs
    std::vector<MarkerSample> samples;
    FrameBlobs blobs;
  };
  std::deque<std::shared_ptr<const Chunk>> window_;  // one chunk per frame set
  size_t window_samples_ = 0;
  uint64_t window_frames_ = 1;
  uint64_t check_frames_ = 1;
  uint64_t stride_ = 1;
  uint64_t resolve_frames_ = 0;
  uint64_t next_check_frame_ = 0;
  bool solved_any_ = false;
  uint64_t last_solve_frame_ = 0;
  bool started_ = false;
  std::future<CheckResult> pending_;
  std::vector<CameraStatus> cameras_;
  uint64_t checks_ = 0;
  uint64_t last_frame_ = 0;
  double baseline_px_ = 0.0;
  std::string last_error_;
};

}  // namespace mocap::service

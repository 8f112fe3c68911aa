// Live wanding in `serve`, the solving part: one worker thread reads the recorded wand session,
// runs the wand calibration (calib/wand_calibration.h) on it and writes beside the session
// wand_calibration.json (the calibration with its report), wand_figures.json and
// wand_report.html (calib/wand_report.h); for a single marker waved, the single-marker
// calibration (calib/single_marker_calibration.h) and wand_calibration.json only. The loop thread polls done() and never waits for it,
// so the frame path is never blocked by a solve.
//
// Threads: the constructor starts the worker; done() and outcome() may be called from any
// thread (outcome() only after done() returned true); the destructor joins. Error policy: no
// exception leaves the worker; a failed solve is an Outcome with ok = false and the reason.
#pragma once

#include <atomic>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "calib/single_marker_calibration.h"
#include "calib/wand_calibration.h"
#include "calib/wand_quality.h"
#include "geometry/camera.h"
#include "ingest/camera_frame.h"

namespace mocap::service {

struct WandSolveInput {
  std::string session_dir;
  std::string title;          // the session's name, for the report
  Rig intrinsics;
  WandGeometry wand;
  WandCalibrationOptions options;
  RatingThresholds thresholds;
  bool single_marker = false;     // one marker waved: the single-marker solve, scale from the bar
  SingleMarkerOptions single_marker_options;
};

struct WandSolveOutcome {
  bool ok = false;
  std::string error;              // why no calibration came out (ok = false)
  bool all_accepted = false;
  Rig rig;                        // accepted cameras
  nlohmann::json report;          // WandResultJson: figures and ratings per camera (single marker:
                                  // SingleMarkerReportJson)
  nlohmann::json calibration;     // the calibration document as written
  std::string calibration_file;   // SESSION/wand_calibration.json
  std::string report_file;        // SESSION/wand_report.html ("" for a single marker)
  std::string figures_file;       // SESSION/wand_figures.json ("" for a single marker)
  double seconds = 0.0;           // wall clock of the whole job
};

class WandSolveJob {
 public:
  explicit WandSolveJob(WandSolveInput input);
  ~WandSolveJob();
  WandSolveJob(const WandSolveJob&) = delete;
  WandSolveJob& operator=(const WandSolveJob&) = delete;

  bool done() const { return done_.load(std::memory_order_acquire); }
  const WandSolveOutcome& outcome() const { return outcome_; }  // after done()

 private:
  void Run();
  void SolveWand(const std::vector<FrameSet>& frames);
  void SolveSingleMarker(const std::vector<FrameSet>& frames);

  WandSolveInput input_;
  WandSolveOutcome outcome_;
  std::atomic<bool> done_{false};
  std::thread worker_;
};

}  // namespace mocap::service

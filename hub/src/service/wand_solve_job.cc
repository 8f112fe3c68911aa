// The wand solve's worker thread (see wand_solve_job.h).
#include "service/wand_solve_job.h"

#include <chrono>
#include <filesystem>
#include <utility>

#include "calib/session_frames.h"
#include "calib/single_marker_report.h"
#include "calib/wand_report.h"
#include "io/calibration_json.h"
#include "util/json_file.h"
#include "util/log.h"
#include "util/thread_priority.h"

namespace mocap::service {

WandSolveJob::WandSolveJob(WandSolveInput input) : input_(std::move(input)), worker_([this] {
      SetThisThreadPriority(ThreadPriority::kBackground);  // the live frames go on meanwhile
      Run();
    }) {}

WandSolveJob::~WandSolveJob() {
  if (worker_.joinable()) worker_.join();
}

void WandSolveJob::Run() {
  const auto start = std::chrono::steady_clock::now();
  WandSolveOutcome& out = outcome_;
  try {
    std::vector<std::string> warnings;
    const std::vector<FrameSet> frames = LoadSessionFrames(input_.session_dir, &warnings);
    for (const std::string& w : warnings) log::Warn("{}: {}", input_.session_dir, w);
    if (input_.single_marker)
      SolveSingleMarker(frames);
    else
      SolveWand(frames);
  } catch (const std::exception& e) {
    out.ok = false;
    out.error = e.what();
  }
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  done_.store(true, std::memory_order_release);
}

void WandSolveJob::SolveWand(const std::vector<FrameSet>& frames) {
  WandSolveOutcome& out = outcome_;
  const WandCalibrationResult result = CalibrateWand(frames, input_.intrinsics, input_.wand, input_.options);
  const nlohmann::json figures = WandReportFigures(result, input_.wand, input_.thresholds, input_.title);
  out.report = WandResultJson(result, input_.wand, input_.thresholds);
  out.calibration = WandCalibrationDocument(result, out.report);
  const std::filesystem::path dir(input_.session_dir);
  out.calibration_file = (dir / "wand_calibration.json").string();
  out.report_file = (dir / "wand_report.html").string();
  out.figures_file = (dir / "wand_figures.json").string();
  WriteJsonFile(out.calibration, out.calibration_file);
  WriteWandReport(figures, out.report_file, out.figures_file);
  out.rig = result.rig;
  out.all_accepted = result.AllAccepted();
  out.ok = true;
}

// Every camera is posed or the solve throws (with the reason), so a result is all accepted.
void WandSolveJob::SolveSingleMarker(const std::vector<FrameSet>& frames) {
  WandSolveOutcome& out = outcome_;
  const SingleMarkerResult result = CalibrateSingleMarker(frames, input_.intrinsics, input_.single_marker_options);
  out.report = SingleMarkerReportJson(result, input_.single_marker_options, input_.title);
  out.calibration = SingleMarkerCalibrationDocument(result, out.report);
  out.calibration_file = (std::filesystem::path(input_.session_dir) / "wand_calibration.json").string();
  WriteJsonFile(out.calibration, out.calibration_file);
  out.rig = result.rig;
  out.all_accepted = true;
  out.ok = true;
}

}  // namespace mocap::service

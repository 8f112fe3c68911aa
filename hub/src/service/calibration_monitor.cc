// The live calibration monitor: a sliding window of marker samples, checks on a worker thread.
#include "service/calibration_monitor.h"

#include <chrono>
#include <cmath>
#include <exception>
#include <iterator>
#include <stdexcept>

#include "util/log.h"
#include "util/thread_priority.h"

namespace mocap::service {

void CalibrationMonitorOptions::Check() const {
  if (!(window_s >= 0.1 && window_s <= 600.0)) throw std::invalid_argument("calibration monitor window_s must be within [0.1, 600]");
  if (!(check_every_s >= 0.05 && check_every_s <= 3600.0))
    throw std::invalid_argument("calibration monitor check_every_s must be within [0.05, 3600]");
  if (!(resolve_every_s >= 0.0 && resolve_every_s <= 86400.0))
    throw std::invalid_argument("calibration monitor resolve_every_s must be within [0, 86400]");
  if (frames_per_window < 10 || frames_per_window > 100000)
    throw std::invalid_argument("calibration monitor frames_per_window must be within [10, 100000]");
  residuals.Check();
  refinement.Check();
}

CalibrationMonitor::CalibrationMonitor(const Rig& rig, double rate_hz, const CalibrationMonitorOptions& options)
    : rig_(rig), options_((options.Check(), options)), collector_(rig, options.residuals), cameras_(rig.cameras.size()) {
  if (!(rate_hz > 0.0) || !std::isfinite(rate_hz)) throw std::invalid_argument("calibration monitor: rate must be > 0");
  window_frames_ = std::max<uint64_t>(1, static_cast<uint64_t>(std::llround(options.window_s * rate_hz)));
  check_frames_ = std::max<uint64_t>(1, static_cast<uint64_t>(std::llround(options.check_every_s * rate_hz)));
  resolve_frames_ = static_cast<uint64_t>(std::llround(options.resolve_every_s * rate_hz));
  stride_ = std::max<uint64_t>(1, window_frames_ / static_cast<uint64_t>(options.frames_per_window));
}

CalibrationMonitor::~CalibrationMonitor() {
  if (pending_.valid()) pending_.wait();
}

void CalibrationMonitor::Add(const FrameSet& set, const Reconstructor& reconstructor) {
  if (pending_.valid() && pending_.wait_for(std::chrono::seconds(0)) == std::future_status::ready)
    TakeResult(pending_.get());
  const uint64_t frame = set.frame_number;
  if (!started_) {
    started_ = true;
    next_check_frame_ = frame + check_frames_;
  }
  last_frame_ = frame;
  if (frame % stride_ == 0) {
    // Each frame set's samples become one shared, immutable chunk: a check's snapshot of the
    // window is then a copy of pointers, not of the samples.
    collector_.AddReconstructed(set, reconstructor);
    std::deque<MarkerSample>& fresh = *collector_.mutable_samples();
    std::deque<FrameBlobs>& blobs = *collector_.mutable_blobs();
    if (!fresh.empty() && !blobs.empty()) {
      auto chunk = std::make_shared<Chunk>();
      chunk->samples.assign(std::make_move_iterator(fresh.begin()), std::make_move_iterator(fresh.end()));
      chunk->blobs = std::move(blobs.back());
      window_samples_ += chunk->samples.size();
      window_.push_back(std::move(chunk));
    }
    fresh.clear();
    blobs.clear();
  }
  while (!window_.empty() && window_.front()->blobs.frame + window_frames_ < frame) {
    window_samples_ -= window_.front()->samples.size();
    window_.pop_front();
  }
  if (frame >= next_check_frame_ && !pending_.valid()) {
    StartCheck(frame);
    next_check_frame_ = frame + check_frames_;
  }
}

void CalibrationMonitor::Finish() {
  if (pending_.valid()) TakeResult(pending_.get());
}

void CalibrationMonitor::StartCheck(uint64_t frame) {
  const bool may_solve = options_.refine && (!solved_any_ || frame >= last_solve_frame_ + resolve_frames_);
  // The worker gets copies: the loop goes on collecting while it judges and solves.
  pending_ = std::async(std::launch::async, [rig = rig_, window = window_, options = options_, frame, may_solve]() {
    SetThisThreadPriority(ThreadPriority::kBackground);  // never ahead of the frame path
    CheckResult result;
    result.frame = frame;
    try {
      std::deque<MarkerSample> samples;
      std::deque<FrameBlobs> blobs;
      for (const auto& chunk : window) {
        samples.insert(samples.end(), chunk->samples.begin(), chunk->samples.end());
        blobs.push_back(chunk->blobs);
      }
      result.detection = DetectBumps(ComputeCameraResiduals(rig, samples), options.refinement.detection);
      if (may_solve && result.detection.AnyMoved())
        result.refinement = RefineExtrinsics(rig, samples, blobs, options.refinement);
    } catch (const std::exception& error) {
      result.error = error.what();
    }
    return result;
  });
}

void CalibrationMonitor::TakeResult(CheckResult result) {
  ++checks_;
  if (!result.error.empty() && result.error != last_error_) log::Warn("calibration monitor: {}", result.error);
  last_error_ = result.error;
  if (result.detection.cameras.size() != cameras_.size()) return;
  baseline_px_ = result.detection.baseline_px;
  for (size_t c = 0; c < cameras_.size(); ++c) {
    CameraStatus& status = cameras_[c];
    const CameraVerdict& verdict = result.detection.cameras[c];
    status.residuals = verdict.residuals;
    if (verdict.state == status.state) continue;
    const uint32_t id = rig_.cameras[c].id;
    if (verdict.state == CameraPoseState::kBumped || verdict.state == CameraPoseState::kDrifting) {
      log::Warn("calibration monitor: camera {} {} (median residual {:.2f} px, rig {:.2f} px, {} views, frame {})", id,
                CameraPoseStateName(verdict.state), verdict.residuals.median_px, result.detection.baseline_px,
                verdict.residuals.observations, result.frame);
    } else if (status.state != CameraPoseState::kUnknown || verdict.state != CameraPoseState::kOk) {
      log::Info("calibration monitor: camera {} {} (median residual {:.2f} px)", id, CameraPoseStateName(verdict.state),
                verdict.residuals.median_px);
    }
    status.state = verdict.state;
    status.since_frame = result.frame;
  }
  if (!result.refinement) return;
  solved_any_ = true;
  last_solve_frame_ = result.frame;
  for (size_t c = 0; c < cameras_.size(); ++c) {
    const CameraRefinement& refined = result.refinement->cameras[c];
    if (!refined.refined) continue;
    CameraStatus& status = cameras_[c];
    status.solved_frame = result.frame;
    status.centre_change_mm = refined.centre_change_mm;
    status.rotation_change_deg = refined.rotation_change_deg;
    status.residual_after_px = refined.after.median_px;
    status.note = refined.note;
    if (refined.accepted) {
      status.solved = result.refinement->rig.cameras[c];
      log::Warn("calibration monitor: camera {} re-solved from the last {:.1f} s: moved {:.2f} mm, turned {:.3f} deg; "
                "median residual {:.2f} -> {:.2f} px (the live reconstruction keeps the old pose until it is applied: "
                "POST /api/calibration/monitor/apply {{\"camera\": {}}})",
                refined.camera_id, options_.window_s, refined.centre_change_mm, refined.rotation_change_deg,
                refined.before.median_px, refined.after.median_px, refined.camera_id);
    } else {
      status.solved.reset();
      log::Warn("calibration monitor: camera {} could not be re-solved: {}", refined.camera_id, refined.note);
    }
  }
}

nlohmann::json CalibrationMonitor::StatusJson() const {
  nlohmann::json cameras = nlohmann::json::array();
  for (size_t c = 0; c < cameras_.size(); ++c) {
    const CameraStatus& s = cameras_[c];
    nlohmann::json camera = {{"id", rig_.cameras[c].id},
                             {"state", CameraPoseStateName(s.state)},
                             {"since_frame", s.since_frame},
                             {"median_px", s.residuals.median_px},
                             {"rms_px", s.residuals.rms_px},
                             {"views", s.residuals.observations}};
    if (s.solved_frame > 0) {
      nlohmann::json solve = {{"frame", s.solved_frame},
                              {"accepted", s.solved.has_value()},
                              {"centre_change_mm", s.centre_change_mm},
                              {"rotation_change_deg", s.rotation_change_deg},
                              {"median_px_after", s.residual_after_px}};
      if (s.solved) {
        nlohmann::json rotation = nlohmann::json::array();
        for (int r = 0; r < 3; ++r)
          rotation.push_back({s.solved->rotation(r, 0), s.solved->rotation(r, 1), s.solved->rotation(r, 2)});
        solve["rotation"] = rotation;
        solve["translation"] = {s.solved->translation.x(), s.solved->translation.y(), s.solved->translation.z()};
      }
      if (!s.note.empty()) solve["note"] = s.note;
      camera["solve"] = solve;
    }
    cameras.push_back(camera);
  }
  nlohmann::json status = {{"window_s", options_.window_s},
                           {"checks", checks_},
                           {"samples", window_samples_},
                           {"baseline_px", baseline_px_},
                           {"cameras", cameras}};
  if (!last_error_.empty()) status["error"] = last_error_;
  return status;
}

}  // namespace mocap::service

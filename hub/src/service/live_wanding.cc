// Live wanding's state (see live_wanding.h).
#include "service/live_wanding.h"

#include <filesystem>
#include <utility>

#include "calib/wand_bundle_adjustment.h"
#include "service/api_error.h"
#include "util/log.h"

namespace mocap::service {

const char* WandingStateName(WandingState state) {
  switch (state) {
    case WandingState::kIdle: return "idle";
    case WandingState::kCollecting: return "collecting";
    case WandingState::kSolving: return "solving";
    case WandingState::kSolved: return "solved";
    case WandingState::kFailed: return "failed";
    case WandingState::kCancelled: return "cancelled";
  }
  return "unknown";
}

void LiveWanding::CheckCanStart() const {
  if (state_ == WandingState::kCollecting)
    throw ApiError(409, "wanding " + options_.session + " is running already");
  if (state_ == WandingState::kSolving) throw ApiError(409, "the last wanding is still being solved");
}

void LiveWanding::Start(std::unique_ptr<WandCollection> collection) {
  CheckCanStart();
  options_ = collection->options();
  collection_ = std::move(collection);
  state_ = WandingState::kCollecting;
  stop_reason_.clear();
  collected_ = nullptr;
  job_.reset();
  applied_ = false;
  saved_to_.clear();
}

void LiveWanding::Stop(const std::string& reason, uint64_t now_ns, bool solve, const std::string& sessions_dir,
                       const Rig& calibration) {
  if (!collecting()) throw ApiError(409, "no wanding is running");
  collected_ = collection_->Json(now_ns);
  stop_reason_ = reason;
  collection_.reset();
  if (!solve) {
    state_ = WandingState::kCancelled;
    return;
  }
  StartSolve(sessions_dir, calibration);
}

void LiveWanding::SolveAgain(const std::string& refine_intrinsics, const std::string& sessions_dir,
                             const Rig& calibration) {
  Poll();
  if (state_ == WandingState::kIdle) throw ApiError(409, "no wanding was recorded since serve started");
  if (state_ == WandingState::kCollecting || state_ == WandingState::kSolving)
    throw ApiError(409, "wanding " + options_.session + " is still " + WandingStateName(state_));
  if (!refine_intrinsics.empty()) options_.refine_intrinsics = refine_intrinsics;
  job_.reset();
  applied_ = false;
  saved_to_.clear();
  StartSolve(sessions_dir, calibration);
}

void LiveWanding::StartSolve(const std::string& sessions_dir, const Rig& calibration) {
  WandSolveInput input;
  input.session_dir = (std::filesystem::path(sessions_dir) / options_.session).string();
  input.title = options_.session;
  input.intrinsics = options_.intrinsics ? *options_.intrinsics : calibration;
  input.wand = options_.Wand();
  input.options.bundle.refine_intrinsics = IntrinsicsRefinementFromName(options_.refine_intrinsics);
  input.options.bundle.num_threads = 1;  // one core for the solve, the other for the frame path
  input.thresholds = options_.thresholds;
  input.single_marker = options_.SingleMarker();
  input.single_marker_options.scale_length_mm = options_.wand_length_mm;
  input.single_marker_options.num_threads = 1;
  job_ = std::make_unique<WandSolveJob>(std::move(input));
  state_ = WandingState::kSolving;
}

void LiveWanding::Poll() {
  if (state_ != WandingState::kSolving || !job_->done()) return;
  const WandSolveOutcome& o = job_->outcome();
  state_ = o.ok ? WandingState::kSolved : WandingState::kFailed;
  if (o.ok)
    log::Info("wanding {}: solved in {:.1f} s, rig rated {}, {}", options_.session, o.seconds,
              o.report.value("rating", ""), o.all_accepted ? "every camera accepted" : "some cameras refused");
  else
    log::Warn("wanding {}: no calibration: {}", options_.session, o.error);
}

const WandSolveOutcome& LiveWanding::Solved() const {
  if (state_ != WandingState::kSolved)
    throw ApiError(409, std::string("no solved wand calibration to apply (state ") + WandingStateName(state_) + ")");
  return job_->outcome();
}

void LiveWanding::Applied(const std::string& saved_to) {
  applied_ = true;
  if (!saved_to.empty()) saved_to_ = saved_to;
}

namespace {

// The files the solve wrote beside the session (a single marker's: the calibration only).
nlohmann::json Files(const WandSolveOutcome& o) {
  if (!o.ok) return nullptr;
  const auto name = [](const std::string& path) {
    return path.empty() ? nlohmann::json(nullptr) : nlohmann::json(std::filesystem::path(path).filename().string());
  };
  return {{"calibration", name(o.calibration_file)}, {"report", name(o.report_file)}, {"figures", name(o.figures_file)}};
}

}  // namespace

nlohmann::json LiveWanding::Json(uint64_t now_ns) const {
  nlohmann::json j = {{"state", WandingStateName(state_)},
                      {"session", options_.session},
                      {"wand_length_mm", options_.wand_length_mm},
                      {"middle_marker_mm", options_.middle_marker_mm},
                      {"stop_reason", stop_reason_},
                      {"applied", applied_},
                      {"saved_to", saved_to_.empty() ? nlohmann::json(nullptr) : nlohmann::json(saved_to_)}};
  j["mode"] = options_.mode;
  j["collection"] = collection_ ? collection_->Json(now_ns) : collected_;
  if (job_ && job_->done()) {
    const WandSolveOutcome& o = job_->outcome();
    j["solve"] = {{"ok", o.ok},
                  {"error", o.error},
                  {"seconds", o.seconds},
                  {"all_accepted", o.all_accepted},
                  {"report", o.report},
                  {"files", Files(o)}};
  } else {
    j["solve"] = nullptr;
  }
  return j;
}

}  // namespace mocap::service

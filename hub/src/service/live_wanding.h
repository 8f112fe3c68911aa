// Live wanding's state in `serve`, one object: what was asked (WandingOptions), where it is
// (an enum state machine), the collection while it runs and its last figures after, the solve
// and whether its calibration was applied. HubService owns one on its loop and does what needs
// the rest of the service (the capture the wand is recorded into, the rig, saving a file); this
// object decides what is allowed when:
//
//   idle ──Start──► collecting ──Stop, solve──► solving ──Poll: job done──► solved | failed
//                        └──────Stop, cancel─► cancelled
//   solved, failed, cancelled ──SolveAgain──► solving;  any but collecting, solving ──Start──► collecting
//
// Error policy: a request the state does not allow throws ApiError 409 with the state's name.
// Threads: the loop's only; the solve runs on WandSolveJob's worker.
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include <nlohmann/json.hpp>

#include "geometry/camera.h"
#include "ingest/camera_frame.h"
#include "service/wand_collection.h"
#include "service/wand_solve_job.h"
#include "service/wanding_options.h"

namespace mocap::service {

enum class WandingState { kIdle, kCollecting, kSolving, kSolved, kFailed, kCancelled };

// "idle", "collecting", "solving", "solved", "failed", "cancelled" (the API's "state").
const char* WandingStateName(WandingState state);

class LiveWanding {
 public:
  // Refuses while collecting or solving (409), before the caller starts the wand's capture.
  void CheckCanStart() const;
  // `collection` was made from the options (which checked them); forgets the last wanding's
  // figures, solve and application.
  void Start(std::unique_ptr<WandCollection> collection);

  bool collecting() const { return state_ == WandingState::kCollecting; }
  WandingState state() const { return state_; }
  const WandingOptions& options() const { return options_; }

  // While collecting: a frame set into the coverage; why collection should stop now, or "".
  void Add(const FrameSet& set) { collection_->Add(set); }
  std::string StopReason(uint64_t now_ns) const { return collection_->StopReason(now_ns); }

  // Collection ends (409 when not collecting; the caller has stopped the capture, so the session
  // is complete on disk): its figures and the reason are kept; then cancelled, or solving: the
  // session SESSIONS_DIR/NAME solved on a worker with the request's intrinsics, else
  // `calibration`'s.
  void Stop(const std::string& reason, uint64_t now_ns, bool solve, const std::string& sessions_dir,
            const Rig& calibration);
  // The last recorded wanding solved again (409 when there is none, or it is still collecting or
  // solving); "" keeps the intrinsics refinement it was started with.
  void SolveAgain(const std::string& refine_intrinsics, const std::string& sessions_dir, const Rig& calibration);

  // Solving becomes solved or failed when the worker is done (logged); otherwise nothing.
  void Poll();
  // The solved outcome (409 when the state is not solved).
  const WandSolveOutcome& Solved() const;
  // Its calibration was applied, and saved to `saved_to` ("" when not saved).
  void Applied(const std::string& saved_to);

  // {"state", "mode", "session", "wand_length_mm", "middle_marker_mm", "stop_reason", "applied",
  //  "saved_to", "collection", "solve"} (GET /api/calibration/wand).
  nlohmann::json Json(uint64_t now_ns) const;

 private:
  void StartSolve(const std::string& sessions_dir, const Rig& calibration);

  WandingState state_ = WandingState::kIdle;
  WandingOptions options_;
  std::unique_ptr<WandCollection> collection_;  // while collecting
  nlohmann::json collected_;                    // the collection's figures when it stopped
  std::string stop_reason_;
  std::unique_ptr<WandSolveJob> job_;
  bool applied_ = false;
  std::string saved_to_;                        // where the applied calibration was saved, if it was
};

}  // namespace mocap::service

// What the live hub offers its clients, apart from how they reach it: the HTTP/WebSocket API
// (api_router.h) calls it, HubService implements it, tests and the request fuzzer fake it.
// Every method may throw ApiError (api_error.h) with the status that says whose fault it was.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "service/wanding_options.h"
#include "service/world_frame_step.h"

namespace mocap::service {

// What an operator may change on a camera; absent fields stay as they are.
struct CameraSettings {
  std::optional<uint32_t> threshold;      // 1..255
  bool auto_threshold = false;
  std::optional<uint32_t> exposure_us;    // 1..1 000 000
  std::optional<uint32_t> gain_milli;     // 1000..64 000
  std::optional<uint32_t> brightness_pct; // 0..100 % of the camera's range (webcams)
  std::optional<uint32_t> contrast_pct;   // 0..100 % of the camera's range
};

class ServiceApi {
 public:
  virtual ~ServiceApi() = default;
  virtual nlohmann::json Status() = 0;
  virtual nlohmann::json Nodes() = 0;
  virtual nlohmann::json Node(uint32_t node_id) = 0;
  virtual nlohmann::json Configure(uint32_t node_id, const CameraSettings& settings) = 0;
  virtual nlohmann::json Identify(uint32_t node_id, uint32_t duration_ms) = 0;
  // PNG bytes of the node's next preview.
  virtual std::vector<uint8_t> PreviewPng(uint32_t node_id, bool thresholded, uint32_t downscale) = 0;
  virtual nlohmann::json AutoMask(int frames) = 0;
  virtual nlohmann::json ClearMasks() = 0;
  virtual nlohmann::json StartCapture(const std::string& name) = 0;
  virtual nlohmann::json StopCapture() = 0;
  virtual nlohmann::json Sessions() = 0;
  // One session with its files; the path of one file of it (see Captures::Describe/FilePath).
  virtual nlohmann::json Session(const std::string& name) = 0;
  virtual std::string SessionFile(const std::string& name, const std::string& file) = 0;
  // Housekeeping (Captures::Delete/Rename/SetNotes): refused 409 for the running capture and for
  // a session a processing job is queued for or running on.
  virtual nlohmann::json DeleteSession(const std::string& name) = 0;
  virtual nlohmann::json RenameSession(const std::string& name, const std::string& new_name) = 0;
  virtual nlohmann::json AnnotateSession(const std::string& name, const std::string& notes) = 0;
  // The cameras of the calibration: id, image size, intrinsics, cam_from_world, centre in world.
  virtual nlohmann::json Calibration() = 0;
  // The 2D blobs of the next frame set per calibrated camera, with each camera's mask regions:
  // {"frame": N | null, "cameras": [{"id", "width", "height", "seen", "blobs": [[x, y, area], ...],
  // "mask": [[x, y, width, height], ...]}]}; "frame" is null when no frame set came in time.
  virtual nlohmann::json Blobs() = 0;
  // Live wanding (wand_collection.h): start a wand capture with live coverage, its state (the
  // coverage while collecting, the solve's report after), stop (and solve, or cancel), solve again, and apply
  // the solved calibration to the live reconstruction (and save it as serve's calibration).
  virtual nlohmann::json StartWanding(const WandingOptions& options) = 0;
  virtual nlohmann::json Wanding() = 0;
  virtual nlohmann::json StopWanding(bool solve) = 0;
  // Solve the last recorded wanding again (after a cancel, a failure or with another intrinsics
  // refinement: "" keeps the one it was started with).
  virtual nlohmann::json SolveWanding(const std::string& refine_intrinsics) = 0;
  virtual nlohmann::json ApplyWandCalibration(bool save) = 0;
  // The calibration monitor's accepted solve of a moved camera (calibration_monitor.h) applied to
  // the live reconstruction (and saved as serve's calibration); answers the monitor's status.
  virtual nlohmann::json ApplyMonitorSolve(uint32_t camera_id, bool save) = 0;
  // The floor / L-frame step (world_frame_step.h): a window of live frame sets with the L-frame
  // (or floor markers) lying still, the world put on it, applied to the live reconstruction and
  // saved as serve's calibration (the old file kept); answers the step's report.
  virtual nlohmann::json SetWorldFrame(const WorldFrameRequest& request) = 0;
  // Processing jobs (processing_jobs.h): a complete session queued for processing by a recipe (the
  // job's description), every job, and one file of a session's results (SESSION/processed/RECIPE/FILE).
  virtual nlohmann::json ProcessSession(const std::string& name, const nlohmann::json& request) = 0;
  virtual nlohmann::json Processing() = 0;
  virtual std::string ProcessedFile(const std::string& name, const std::string& recipe, const std::string& file) = 0;
  // The trajectory editor's log of a recipe's results, and a new log applied to them
  // (processed_edits.h: the log saved and the edited outputs written only when it applies).
  virtual nlohmann::json ProcessedEdits(const std::string& name, const std::string& recipe) = 0;
  virtual nlohmann::json PutProcessedEdits(const std::string& name, const std::string& recipe, const nlohmann::json& log) = 0;
};

}  // namespace mocap::service

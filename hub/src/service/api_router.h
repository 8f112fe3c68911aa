// The live hub's HTTP API as a pure function: method, path, query and body in, status, content
// type and body out, over a ServiceApi. No sockets here, so the whole request surface is unit
// tested and fuzzed; the HTTP server (http_server.h) only moves bytes.
//
//   GET    /api/status                      the service: uptime, frame sets, latency, capture
//   GET    /api/nodes                       the node table
//   GET    /api/nodes/ID                    one node
//   POST   /api/nodes/ID/settings           {"threshold": N | "auto_threshold": true,
//                                            "exposure_us": N, "gain_milli": N} (any of them)
//   POST   /api/nodes/ID/identify           {"duration_ms": N} (optional, default 3000)
//   GET    /api/nodes/ID/preview?mode=raw|thresholded&downscale=1|2|4|8   image/png
//   POST   /api/masks/auto                  {"frames": N} (default 100)
//   DELETE /api/masks                       every camera's mask removed
//   POST   /api/capture/start               {"name": "NAME"}
//   POST   /api/capture/stop
//   GET    /api/sessions                    every session with its state
//   GET    /api/sessions/NAME               one session with its files
//   GET    /api/sessions/NAME/files/FILE    one of them (the response names the file to send)
//   POST   /api/sessions/NAME/process       {"recipe": {recipe fields}, "overwrite": false}: 202 and
//                                            the queued job (processing_jobs.h)
//   GET    /api/sessions/NAME/processed/RECIPE/files/FILE   one file of a recipe's results
//   GET    /api/sessions/NAME/processed/RECIPE/edits   the trajectory editor's log of those results
//   PUT    /api/sessions/NAME/processed/RECIPE/edits   {edit log}: applied, saved, edited outputs
//                                            written (processed_edits.h); 400 names the operation
//   GET    /api/processing                  every processing job: state, progress, log, outputs
//   GET    /api/calibration                 the cameras: intrinsics, pose, centre
//   GET    /api/blobs                       every camera's 2D blobs of the next frame set, masks
//   POST   /api/calibration/wand/start      {"name", "mode": "wand"|"single-marker", "wand_length_mm",
//                                            "middle_marker_mm", "min_samples", "min_scale_frames",
//                                            "coverage_target", "timeout_s", "refine_intrinsics",
//                                            "intrinsics": {calibration JSON}, "grid_columns",
//                                            "grid_rows", "cell_samples"} (name and length required;
//                                            single-marker: the length is the scale bar's)
//   GET    /api/calibration/wand            the wanding: coverage per camera, advice, the solve
//   POST   /api/calibration/wand/stop       {"solve": true|false} (default true)
//   POST   /api/calibration/wand/solve      {"refine_intrinsics"}: solve the recorded wanding again
//   POST   /api/calibration/wand/apply      {"save": true|false} (default false)
//   POST   /api/calibration/monitor/apply   {"camera": ID, "save": true|false}: the monitor's
//                                            solved pose of a moved camera, applied live
//
// Errors: {"error": "reason"} with 400 (bad JSON, unknown field, value out of range), 404 (no
// such path or node), 405 (wrong method), 409, 413 (body over 64 KiB), 504, 500.
#pragma once

#include <string>

#include "service/service_api.h"

namespace mocap::service {

struct ApiRequest {
  std::string method;  // "GET", "POST", ...
  std::string path;    // "/api/nodes/3/preview"
  std::string query;   // "mode=raw&downscale=2" (no '?')
  std::string body;
};

struct ApiResponse {
  int status = 200;
  std::string content_type = "application/json";
  std::string body;
  std::string file;  // when set, the answer is this file's content (body unused): a download
};

inline constexpr size_t kMaxApiBody = 64 * 1024;

ApiResponse HandleApiRequest(ServiceApi& api, const ApiRequest& request);

}  // namespace mocap::service

// The floor / L-frame step after wanding, in `serve` (POST /api/calibration/world; ServiceApi's
// SetWorldFrame): a wand calibration's world is its reference camera's, so the live view hangs
// tilted until the world is put on the floor. The service collects a short window of live frame
// sets while an L-frame (or floor markers) lies still, and this module solves the world transform
// from them (calib/world_frame.h, as `calibrate world` does offline) and describes what it found:
// the markers, the fit, how far the world moved and turned and how much tilt it removed.
//
// Error policy: WorldFrameRequest::Check throws ApiError 400 naming the field; SolveWorldFrame
// throws ApiError 422 with what was seen and what to do when the L-frame (or floor) is not found.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "geometry/camera.h"
#include "ingest/camera_frame.h"

namespace mocap::service {

inline constexpr const char* kWorldMethodLFrame = "lframe";
inline constexpr const char* kWorldMethodFloor = "floor";

struct WorldFrameRequest {
  std::string method = kWorldMethodLFrame;  // lframe: an L-frame; floor: markers lying on the floor
  int frames = 60;                          // live frame sets collected, 10..2000
  int up_axis = 2;                          // the new world's vertical axis: 0 x, 1 y, 2 z
  std::vector<Eigen::Vector3d> lframe;      // its markers in the new world, mm; empty: DefaultLFrame
  double max_fit_rms_mm = 6.0;              // an L-frame match leaves at most this RMS
  int min_frames = 3;                       // frame sets in which the whole L-frame must be found

  void Check() const;
};

struct WorldFrameSolution {
  Rig rig;              // the same cameras in the new world
  nlohmann::json report;
};

// report: {"method", "up", "frames", "frames_used", "points_per_frame" (median reconstructed),
// "markers": [{"model": [x,y,z] | null, "measured": [x,y,z] (new world), "error_mm" | null}],
// "fit_rms_mm", "moved_mm", "turned_deg", "tilt_removed_deg" (between the old world's vertical
// axis and the new one), "axes": {"x","y","z": each new axis in the old world}}.
WorldFrameSolution SolveWorldFrame(const std::vector<FrameSet>& frames, const Rig& rig,
                                   const WorldFrameRequest& request);

}  // namespace mocap::service

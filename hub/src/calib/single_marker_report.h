// The single-marker calibration written out: its report (figures per camera) and the
// calibration document (the rig with each camera's reprojection RMS, the report under
// "calibration"), shared by `calibrate marker` and serve's live single-marker wanding.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "calib/single_marker_calibration.h"

namespace mocap {

// {"method": "single-marker", "session", "reference_camera", "frames_selected", "frames_used",
//  "scale_frames", "scale_length_mm", "scale_length_rms_mm",
//  "cameras": [{"id", "views", "used", "rms_px", "joined_through"}]}
nlohmann::json SingleMarkerReportJson(const SingleMarkerResult& result, const SingleMarkerOptions& options,
                                      const std::string& session);
// The calibration JSON: RigToJson of the solved rig, each camera's "reprojection_rms_px", and
// `report` under "calibration".
nlohmann::json SingleMarkerCalibrationDocument(const SingleMarkerResult& result, const nlohmann::json& report);

}  // namespace mocap

// The single-marker calibration's report and document (see single_marker_report.h).
#include "calib/single_marker_report.h"

#include "io/calibration_json.h"

namespace mocap {

nlohmann::json SingleMarkerReportJson(const SingleMarkerResult& result, const SingleMarkerOptions& options,
                                      const std::string& session) {
  nlohmann::json cameras = nlohmann::json::array();
  for (const SingleMarkerCamera& camera : result.cameras) {
    cameras.push_back({{"id", camera.id},
                       {"views", camera.views},
                       {"used", camera.used},
                       {"rms_px", camera.rms_px},
                       {"joined_through", camera.joined_through}});
  }
  return {{"method", "single-marker"},
          {"session", session},
          {"reference_camera", result.reference_id},
          {"frames_selected", result.frames_selected},
          {"frames_used", result.frames_used},
          {"scale_frames", result.scale_frames},
          {"scale_length_mm", options.scale_length_mm},
          {"scale_length_rms_mm", result.scale_length_rms_mm},
          {"cameras", cameras}};
}

nlohmann::json SingleMarkerCalibrationDocument(const SingleMarkerResult& result, const nlohmann::json& report) {
  nlohmann::json document = RigToJson(result.rig);
  for (size_t c = 0; c < result.cameras.size(); ++c)
    document["cameras"][c]["reprojection_rms_px"] = result.cameras[c].rms_px;
  document["calibration"] = report;
  return document;
}

}  // namespace mocap

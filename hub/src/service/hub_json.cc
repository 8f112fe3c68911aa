// The live hub's JSON views (see hub_json.h).
#include "service/hub_json.h"

#include "io/calibration_json.h"

namespace mocap::service {
namespace {

// The node's reception figures, or zeros for a node outside the calibration.
const NodeStats& ReceptionOf(const IngestStats& stats, uint32_t node) {
  static const NodeStats kNone;
  auto it = stats.nodes.find(node);
  return it == stats.nodes.end() ? kNone : it->second;
}

}  // namespace

nlohmann::json RequestJson(const RequestResult& r) {
  return {{"node", r.node_id},
          {"outcome", RequestOutcomeName(r.outcome)},
          {"reason", r.reason},
          {"datagrams", r.datagrams},
          {"retransmissions", r.retransmissions},
          {"ms", static_cast<double>(r.finished_ns - r.submitted_ns) * 1e-6}};
}

nlohmann::json NodeJson(const NodeEntry& n, const IngestStats& stats, const std::vector<CameraMask>& masks,
                        uint64_t now_ns) {
  const NodeStats& reception = ReceptionOf(stats, n.id);
  nlohmann::json j = {
      {"id", n.id},
      {"address", n.address},
      {"state", n.lost ? "lost" : NodeStateName(n.state)},
      {"firmware", n.firmware_version},
      {"fps", n.fps},
      {"detect_us_mean", n.detect_time_us_mean},
      {"detect_us_max", n.detect_time_us_max},
      {"frames_captured", n.frames_captured},
      {"frames_sent", n.frames_sent},
      {"frames_dropped", n.frames_dropped},
      {"last_frame", n.last_frame_number},
      {"off_clock_frames", reception.off_clock_frames},
      {"off_clock_s", reception.off_clock_s},
      {"rescaled_frames", reception.rescaled_frames},
      {"wrong_size_frames", reception.wrong_size_frames},
      {"last_seen_s",
       n.last_seen_ns && now_ns > n.last_seen_ns ? static_cast<double>(now_ns - n.last_seen_ns) * 1e-9 : 0.0},
      {"times_lost", n.times_lost},
      {"restarts", n.restarts},
      {"threshold", n.threshold},
      // Recorded frames have no exposure or gain to set: null, not a 0 that reads as a setting.
      {"exposure_fixed", n.exposure_fixed},
      {"exposure_us", n.exposure_fixed ? nlohmann::json(nullptr) : nlohmann::json(n.exposure_us)},
      {"gain_milli", n.exposure_fixed ? nlohmann::json(nullptr) : nlohmann::json(n.gain_milli)},
      {"width", n.width},
      {"height", n.height},
      {"control_rejected", n.control_rejected},
      {"auth_rejected_by_node", n.auth_rejected},
      {"camera_reopens", n.camera_reopens},
      {"sync",
       {{"edge_jitter_ns", n.sync.edge_jitter_ns},
        {"unmatched_frames", n.sync.unmatched_frames},
        {"missed_edges", n.sync.missed_edges},
        {"spurious_edges", n.sync.spurious_edges}}},
      {"has_status", n.has_status},
      {"masked", false},
  };
  j["temperature_c"] = n.has_temperature ? nlohmann::json(n.temperature_c) : nlohmann::json(nullptr);
  for (const CameraMask& m : masks)
    if (m.camera_id == n.id) j["masked"] = !m.regions.empty();
  return j;
}

nlohmann::json CamerasJson(const Rig& rig) {
  nlohmann::json cameras = RigToJson(rig)["cameras"];  // the calibration file's own fields
  for (size_t i = 0; i < rig.cameras.size(); ++i) {
    const Eigen::Vector3d centre = rig.cameras[i].CenterInWorld();
    cameras[i]["centre"] = {centre.x(), centre.y(), centre.z()};
  }
  return cameras;
}

nlohmann::json BlobsJson(const Rig& rig, const BlobsSnapshot& snapshot) {
  const FrameSet* set = snapshot.set ? &*snapshot.set : nullptr;
  nlohmann::json cameras = nlohmann::json::array();
  for (const Camera& c : rig.cameras) {
    nlohmann::json blobs = nlohmann::json::array();
    bool seen = false;
    if (set) {
      for (const CameraFrame& frame : set->cameras) {
        if (frame.camera_id != c.id) continue;
        seen = true;
        for (const Blob& b : frame.blobs) blobs.push_back({b.pixel.x(), b.pixel.y(), b.area});
      }
    }
    nlohmann::json mask = nlohmann::json::array();
    for (const CameraMask& m : snapshot.masks)
      if (m.camera_id == c.id)
        for (const MaskRect& r : m.regions) mask.push_back({r.x, r.y, r.width, r.height});
    cameras.push_back({{"id", c.id},
                       {"width", c.intrinsics.width},
                       {"height", c.intrinsics.height},
                       {"seen", seen},
                       {"blobs", blobs},
                       {"mask", mask}});
  }
  return {{"frame", set ? nlohmann::json(set->frame_number) : nlohmann::json(nullptr)}, {"cameras", cameras}};
}

}  // namespace mocap::service

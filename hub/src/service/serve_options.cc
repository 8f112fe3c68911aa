// serve's options and the options derived from them (see serve_options.h).
#include "service/serve_options.h"

#include <algorithm>
#include <stdexcept>

#include "ingest/udp_socket.h"
#include "io/calibration_json.h"

namespace mocap::service {
namespace {

uint64_t Ns(double seconds) { return static_cast<uint64_t>(seconds * 1e9); }

}  // namespace

FrameSetAssemblerOptions AssemblyOf(const ServeOptions& o, uint64_t epoch_ns) {
  FrameSetAssemblerOptions a;
  a.deadline_ns = static_cast<uint64_t>(o.deadline_ms * 1e6);
  a.free_run = o.free_run;
  a.rate_hz = o.rate_hz;
  a.epoch_ns = epoch_ns;
  return a;
}

std::vector<uint32_t> CameraIds(const Rig& rig) {
  std::vector<uint32_t> ids;
  for (const Camera& c : rig.cameras) ids.push_back(c.id);
  return ids;
}

bool SameCameras(const Rig& a, const Rig& b) {
  std::vector<uint32_t> x = CameraIds(a), y = CameraIds(b);
  std::sort(x.begin(), x.end());
  std::sort(y.begin(), y.end());
  return x == y;
}

NodeRegistryOptions RegistryOf(const ServeOptions& o, const Rig& rig) {
  NodeRegistryOptions r;
  r.lost_after_ns = Ns(o.node_lost_after_s);
  for (const Camera& c : rig.cameras) r.allowed_nodes.insert(c.id);
  return r;
}

ControlRequestsOptions ControlsOf(const ServeOptions& o, uint64_t now_ns) {
  ControlRequestsOptions c;
  c.timeout_ns = Ns(o.request_timeout_s);
  // A restarted hub must not reuse the sequences of a mask image a node may still hold
  // half-assembled: start from the clock (tenths of a second wrap after 13 years).
  c.first_sequence = static_cast<uint32_t>((now_ns / 100'000'000ull) % 0xF0000000ull) + 1;
  return c;
}

Rig LoadServeRig(const std::string& path) {
  if (path.empty()) throw std::invalid_argument("serve needs a calibration (--calibration FILE)");
  Rig rig = LoadRigJson(path);
  if (rig.cameras.size() < 2) throw std::invalid_argument(path + ": needs at least 2 cameras");
  return rig;
}

SessionInfo SessionBase(const ServeOptions& o, const Rig& rig, uint64_t epoch_ns) {
  SessionInfo info;
  info.rate_hz = o.rate_hz;
  info.epoch_ns = epoch_ns;
  info.free_run = o.free_run;
  info.camera_ids = CameraIds(rig);
  return info;
}

uint64_t EpochOf(const ServeOptions& o) { return o.epoch_ns ? o.epoch_ns : RealtimeNowNs(); }

int SkeletonUpAxis(const std::string& text) {
  static const char* const kNames[] = {"x", "y", "z", "-x", "-y", "-z"};
  for (int i = 0; i < 6; ++i)
    if (text == kNames[i]) return i < 3 ? i : -(i - 3) - 1;
  throw std::invalid_argument("skeleton up axis '" + text + "' is not x, y, z, -x, -y or -z");
}

void ServeOptions::Check() const {
  ParseHostPort(listen);
  if (!announce.empty()) ParseHostPort(announce);
  if (!(rate_hz > 0.0 && rate_hz <= 1000.0)) throw std::invalid_argument("rate must be within (0, 1000] Hz");
  if (!(deadline_ms > 0.0 && deadline_ms <= 1000.0)) throw std::invalid_argument("deadline must be within (0, 1000] ms");
  if (!(busy_poll_us >= 0.0 && busy_poll_us <= 100000.0))
    throw std::invalid_argument("busy poll must be within [0, 100000] us");
  if (realtime_priority < 0 || realtime_priority > 99)
    throw std::invalid_argument("realtime priority must be within [0, 99] (0: off)");
  if (!(node_lost_after_s >= 0.5 && node_lost_after_s <= 3600.0))
    throw std::invalid_argument("node-lost-after must be within [0.5, 3600] s");
  if (!(request_timeout_s >= 0.05 && request_timeout_s <= 60.0))
    throw std::invalid_argument("request timeout must be within [0.05, 60] s");
  if (auto_mask_max_frames < 10 || auto_mask_max_frames > 100000)
    throw std::invalid_argument("auto-mask frames limit must be within [10, 100000]");
  if (!skeleton_file.empty() && labels_file.empty())
    throw std::invalid_argument("skeleton " + skeleton_file + " needs a marker set (--labels): it is solved from named markers");
  SkeletonUpAxis(skeleton_up);
  recon.Check();
  tracker.Check();
  body_filter.Check();
  auth.Check();
  if (const std::string error = disk.Check(); !error.empty()) throw std::invalid_argument(error);
}

}  // namespace mocap::service

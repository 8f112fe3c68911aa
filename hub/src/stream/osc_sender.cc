// OSC bundles per frame over liblo (see osc_sender.h).
#include "stream/osc_sender.h"

#include <lo/lo.h>

#include <memory>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "ingest/udp_socket.h"

namespace mocap::stream {
namespace {

constexpr std::chrono::milliseconds kIdleWait{100};

// One message of the address space, built by liblo or described for tests.
template <typename Sink>
void VisitFrame(const pipeline::LiveFrame& frame, uint32_t parts, uint64_t* points_dropped, Sink&& sink) {
  const bool points = parts & kPartPoints, bodies = parts & kPartBodies;
  size_t point_count = points ? std::min(frame.points.size(), kMaxOscPoints) : 0;
  size_t body_count = 0;
  if (bodies)
    for (const pipeline::LiveBody& b : frame.bodies) body_count += b.tracked;
  if (points_dropped) *points_dropped += points ? frame.points.size() - point_count : 0;
  sink.Frame(frame.frame_number, frame.trigger_time_ns, point_count, body_count);
  for (size_t i = 0; i < point_count; ++i) sink.Point(frame.points[i], frame.label_names.get());
  if (bodies)
    for (const pipeline::LiveBody& b : frame.bodies)
      if (b.tracked) sink.Body(b);
  if (parts & kPartBones)
    for (const pipeline::LiveSkeleton& s : frame.skeletons) {
      if (!s.model) continue;
      sink.Skeleton(s);
      for (size_t b = 0; b < s.bones.size() && b < s.model->bones.size(); ++b) sink.Bone(s, b);
    }
}

struct ShapeSink {
  std::vector<OscMessageShape>* out;
  void Frame(uint64_t, uint64_t, size_t, size_t) { out->push_back({"/mocap/frame", "hhii"}); }
  void Point(const pipeline::LivePoint& p, const std::vector<std::string>* names) {
    OscMessageShape shape = p.marker >= 0 ? OscMessageShape{"/mocap/marker", "iffffi"} : OscMessageShape{"/mocap/point", "hffffi"};
    if (names != nullptr) shape.types += "s";
    out->push_back(shape);
  }
  void Body(const pipeline::LiveBody&) { out->push_back({"/mocap/rigidbody", "sffffffff"}); }
  void Skeleton(const pipeline::LiveSkeleton&) { out->push_back({"/mocap/skeleton", "sisiff"}); }
  void Bone(const pipeline::LiveSkeleton&, size_t) { out->push_back({"/mocap/bone", "ssifffffff"}); }
};

struct BundleSink {
  lo_bundle bundle;
  void Add(const char* path, lo_message m) { lo_bundle_add_message(bundle, path, m); }
  void Frame(uint64_t number, uint64_t trigger_ns, size_t points, size_t bodies) {
    lo_message m = lo_message_new();
    lo_message_add_int64(m, static_cast<int64_t>(number));
    lo_message_add_int64(m, static_cast<int64_t>(trigger_ns));
    lo_message_add_int32(m, static_cast<int32_t>(points));
    lo_message_add_int32(m, static_cast<int32_t>(bodies));
    Add("/mocap/frame", m);
  }
  void Point(const pipeline::LivePoint& p, const std::vector<std::string>* names) {
    lo_message m = lo_message_new();
    if (p.marker >= 0)
      lo_message_add_int32(m, static_cast<int32_t>(1 + (p.id - 1) % 0x7fffffffu));
    else
      lo_message_add_int64(m, p.id ? static_cast<int64_t>(p.id) : -1);
    lo_message_add_float(m, static_cast<float>(p.position.x()));
    lo_message_add_float(m, static_cast<float>(p.position.y()));
    lo_message_add_float(m, static_cast<float>(p.position.z()));
    lo_message_add_float(m, static_cast<float>(p.rms_px));
    lo_message_add_int32(m, p.views);
    // With a marker set (serve --labels): the point's name last, empty when it has none.
    if (names != nullptr)
      lo_message_add_string(m, p.label >= 0 && static_cast<size_t>(p.label) < names->size()
                                   ? (*names)[static_cast<size_t>(p.label)].c_str()
                                   : "");
    Add(p.marker >= 0 ? "/mocap/marker" : "/mocap/point", m);
  }
  void Body(const pipeline::LiveBody& b) {
    lo_message m = lo_message_new();
    lo_message_add_string(m, b.name.c_str());
    for (double v : {b.position.x(), b.position.y(), b.position.z(), b.orientation.x(), b.orientation.y(),
                     b.orientation.z(), b.orientation.w(), b.mean_error_mm})
      lo_message_add_float(m, static_cast<float>(v));
    Add("/mocap/rigidbody", m);
  }
  void Skeleton(const pipeline::LiveSkeleton& s) {
    lo_message m = lo_message_new();
    lo_message_add_string(m, s.model->name.c_str());
    lo_message_add_int32(m, s.solved ? 1 : 0);
    lo_message_add_string(m, s.state);
    lo_message_add_int32(m, s.markers);
    lo_message_add_float(m, static_cast<float>(s.rms_mm));
    lo_message_add_float(m, static_cast<float>(s.max_mm));
    Add("/mocap/skeleton", m);
  }
  void Bone(const pipeline::LiveSkeleton& s, size_t b) {
    const pipeline::LiveBone& bone = s.bones[b];
    lo_message m = lo_message_new();
    lo_message_add_string(m, s.model->name.c_str());
    lo_message_add_string(m, s.model->bones[b].c_str());
    lo_message_add_int32(m, s.model->parents[b]);
    for (double v : {bone.position.x(), bone.position.y(), bone.position.z(), bone.orientation.x(),
                     bone.orientation.y(), bone.orientation.z(), bone.orientation.w()})
      lo_message_add_float(m, static_cast<float>(v));
    Add("/mocap/bone", m);
  }
};

}  // namespace

struct OscSender::Targets {
  std::vector<lo_address> addresses;
  ~Targets() {
    for (lo_address a : addresses) lo_address_free(a);
  }
};

void OscOptions::Check() const {
  if (targets.empty()) throw std::invalid_argument("OSC: no targets");
  for (const std::string& t : targets) {
    const HostPort hp = ParseHostPort(t);
    if (hp.host.empty() || hp.port == 0) throw std::invalid_argument("OSC target '" + t + "' must be HOST:PORT");
  }
  if (parts == 0 || (parts & ~(kPartPoints | kPartBodies | kPartBones)))
    throw std::invalid_argument("OSC parts must be points, bodies and/or bones");
  if (ttl < 1 || ttl > 255) throw std::invalid_argument("OSC TTL must be 1-255");
  if (queue_frames == 0) throw std::invalid_argument("OSC queue must hold at least one frame");
}

std::vector<OscMessageShape> OscBundleShape(const pipeline::LiveFrame& frame, uint32_t parts) {
  std::vector<OscMessageShape> out;
  VisitFrame(frame, parts, nullptr, ShapeSink{&out});
  return out;
}

OscSender::OscSender(OscOptions options)
    : options_((options.Check(), std::move(options))), targets_(std::make_unique<Targets>()),
      queue_(options_.queue_frames) {
  for (const std::string& t : options_.targets) {
    const HostPort hp = ParseHostPort(t);
    lo_address a = lo_address_new(hp.host.c_str(), std::to_string(hp.port).c_str());
    if (!a) throw std::invalid_argument("OSC target '" + t + "': liblo cannot use it");
    lo_address_set_ttl(a, options_.ttl);
    targets_->addresses.push_back(a);
  }
  thread_ = std::thread([this] { Run(); });
}

OscSender::~OscSender() {
  stop_ = true;
  queue_.Close();
  if (thread_.joinable()) thread_.join();
}

OscStats OscSender::stats() const {
  std::lock_guard<std::mutex> lock(stats_mutex_);
  OscStats s = stats_;
  s.frames_dropped = queue_.dropped();
  return s;
}

nlohmann::json OscSender::StatsJson() const {
  const OscStats s = stats();
  return {{"targets", options_.targets},
          {"bundles", s.bundles},
          {"send_failures", s.send_failures},
          {"frames_dropped", s.frames_dropped},
          {"points_dropped", s.points_dropped}};
}

void OscSender::Run() {
  while (!stop_) {
    const SharedFrame frame = queue_.Pop(kIdleWait);
    if (!frame) continue;
    lo_bundle bundle = lo_bundle_new(LO_TT_IMMEDIATE);
    uint64_t points_dropped = 0;
    VisitFrame(*frame, options_.parts, &points_dropped, BundleSink{bundle});
    uint64_t sent = 0, failed = 0;
    for (lo_address a : targets_->addresses) (lo_send_bundle(a, bundle) > 0 ? sent : failed)++;
    lo_bundle_free_recursive(bundle);
    std::lock_guard<std::mutex> lock(stats_mutex_);
    stats_.bundles += sent;
    stats_.send_failures += failed;
    stats_.points_dropped += points_dropped;
  }
}

}  // namespace mocap::stream

#include "service/stream_fan_out.h"

#include <filesystem>
#include <sstream>
#include <utility>

#include "bodies/body_definition.h"
#include "ingest/udp_socket.h"
#include "io/calibration_json.h"
#include "labels/marker_set.h"
#include "pipeline/live_skeleton.h"
#include "stream/osc_sender.h"
#include "stream/qtm/qtm_rt_server.h"
#include "stream/qtm/rt_parameters.h"
#include "stream/stream_encoding.h"
#include "stream/vmc_sender.h"
#include "util/log.h"

namespace mocap::service {
namespace {

std::vector<std::string> SplitList(const std::string& text) {
  std::vector<std::string> out;
  std::stringstream in(text);
  for (std::string item; std::getline(in, item, ',');)
    if (!item.empty()) out.push_back(item);
  return out;
}

// Each adapter's options, derived from the streams' options in one place.
stream::UdpStreamOptions UdpOf(const StreamsOptions& o) {
  stream::UdpStreamOptions udp = o.stream;
  udp.multicast_parts = stream::ParseParts(o.stream_multicast_parts);
  return udp;
}

stream::OscOptions OscOf(const StreamsOptions& o) {
  stream::OscOptions osc;
  osc.targets = SplitList(o.osc_targets);
  osc.parts = stream::ParseParts(o.osc_parts);
  return osc;
}

stream::qtm::QtmRtOptions RtOf(const StreamsOptions& o) {
  stream::qtm::QtmRtOptions rt;
  rt.listen = o.qtm_rt;
  return rt;
}

stream::natnet::NatNetOptions NatNetOf(const StreamsOptions& o) {
  stream::natnet::NatNetOptions natnet = o.natnet;
  if (o.natnet_unicast) natnet.multicast.clear();
  return natnet;
}

// The world's up axis comes from the calibration when the sender is made; any axis it can
// name is valid, so the check takes the default.
stream::VmcOptions VmcOf(const StreamsOptions& o, const ServeOptions& serve, const std::string& up_axis = "+Y") {
  stream::VmcOptions vmc;
  vmc.target = o.vmc;
  vmc.rate_hz = serve.rate_hz;
  vmc.up_axis = up_axis;
  return vmc;
}

std::string AnyHost(const std::string& host) { return host.empty() || host == "*" ? "0.0.0.0" : host; }

}  // namespace

void StreamsOptions::Check(const ServeOptions& serve) const {
  if (stream.listen != "off") UdpOf(*this).Check();
  if (!osc_targets.empty()) OscOf(*this).Check();
  if (!qtm_rt.empty()) RtOf(*this).Check();
  if (!natnet.listen.empty()) NatNetOf(*this).Check();
  if (!vrpn.listen.empty()) vrpn.Check();
  if (!vmc.empty()) VmcOf(*this, serve).Check();
}

StreamFanOut::StreamFanOut(const ServeOptions& serve, const StreamsOptions& options, HubService& hub,
                           std::function<void(stream::SharedFrame)> also)
    : options_(options), hub_(hub), also_(std::move(also)) {
  options_.Check(serve);
  if (options_.stream.listen != "off") {
    auto udp = std::make_unique<stream::UdpStreamServer>(UdpOf(options_));
    const std::string& group = options_.stream.multicast;
    std::string where = fmt::format("stream: UDP port {}{}", udp->port(), group.empty() ? "" : ", multicast to " + group);
    Add("stream", std::move(udp), std::move(where));
  }
  if (!options_.osc_targets.empty())
    Add("osc", std::make_unique<stream::OscSender>(OscOf(options_)), "OSC: bundles to " + options_.osc_targets);
  if (!options_.qtm_rt.empty()) {
    auto rt = std::make_unique<stream::qtm::QtmRtServer>(
        RtOf(options_),
        stream::qtm::LoadRtSystem(serve.calibration, serve.rate_hz, serve.bodies_file, serve.labels_file));
    std::string where = fmt::format("Qualisys RT on {}:{}", AnyHost(ParseHostPort(options_.qtm_rt).host), rt->port());
    Add("qtm_rt", std::move(rt), std::move(where));
  }
  AddTrackers(serve);
  frames_id_ = hub_.Subscribe([this](const pipeline::LiveFrame& frame) { Publish(frame); });
  captures_id_ = hub_.SubscribeCaptures([this](const pipeline::CaptureEvent& event) {
    for (Adapter& a : adapters_) a.sink->OnCapture(event);
  });
  for (const Adapter& a : adapters_) {
    const stream::StreamSink* sink = a.sink.get();
    hub_.AddStatusSection(a.name, [sink] { return sink->StatsJson(); });
  }
}

// NatNet, VRPN and VMC: their rigid bodies and names come from serve's bodies and marker-set files.
void StreamFanOut::AddTrackers(const ServeOptions& serve) {
  if (options_.natnet.listen.empty() && options_.vrpn.listen.empty() && options_.vmc.empty()) return;
  const std::vector<RigidBodyDefinition> bodies =
      serve.bodies_file.empty() ? std::vector<RigidBodyDefinition>{} : ReadBodiesFile(serve.bodies_file);
  if (!options_.natnet.listen.empty()) {
    stream::natnet::Model model;
    model.rate_hz = serve.rate_hz;
    model.bodies = bodies;
    if (!serve.labels_file.empty()) model.label_names = ReadMarkerSetFile(serve.labels_file).names;
    if (!serve.skeleton_file.empty())
      model.skeletons = {pipeline::LiveSkeletonModelOf(ReadSkeletonFile(serve.skeleton_file),
                                                       std::filesystem::path(serve.skeleton_file).stem().string())};
    const stream::natnet::NatNetOptions o = NatNetOf(options_);
    auto natnet = std::make_unique<stream::natnet::NatNetServer>(o, std::move(model));
    std::string where = fmt::format("NatNet on {}:{}, frames {}", ParseHostPort(o.listen).host, natnet->port(),
                                    o.multicast.empty() ? std::string("unicast to connected clients")
                                                        : "to " + o.multicast + ":" + std::to_string(o.data_port));
    Add("natnet", std::move(natnet), std::move(where));
  }
  if (!options_.vrpn.listen.empty()) {
    std::vector<std::string> names;
    for (const RigidBodyDefinition& b : bodies) names.push_back(b.name);
    if (names.empty()) log::Warn("vrpn: no rigid bodies (--bodies): no trackers to serve");
    auto vrpn = std::make_unique<stream::vrpn::VrpnServer>(options_.vrpn, std::move(names));
    std::string where = fmt::format("VRPN on {}:{}", ParseHostPort(options_.vrpn.listen).host, vrpn->port());
    Add("vrpn", std::move(vrpn), std::move(where));
  }
  if (!options_.vmc.empty()) {
    const std::string up_axis = stream::qtm::AxisUpwards(LoadRigJson(serve.calibration));
    Add("vmc", std::make_unique<stream::VmcSender>(VmcOf(options_, serve, up_axis)), "VMC: bundles to " + options_.vmc);
  }
}

StreamFanOut::~StreamFanOut() {
  hub_.Unsubscribe(frames_id_);
  hub_.Unsubscribe(captures_id_);
  for (const Adapter& a : adapters_) hub_.RemoveStatusSection(a.name);
}

void StreamFanOut::Add(std::string name, std::unique_ptr<stream::StreamSink> sink, std::string where) {
  adapters_.push_back({std::move(name), std::move(sink), std::move(where)});
}

void StreamFanOut::Publish(const pipeline::LiveFrame& frame) {
  const stream::SharedFrame shared = stream::ShareFrame(frame);
  // Every adapter before the WebSockets' hand-off: the adapters send on this thread, and waking
  // the WebSockets' thread first can let it run ahead of them on a busy core.
  for (const Adapter& a : adapters_) a.sink->Publish(shared);
  if (also_) also_(shared);
}

std::vector<std::string> StreamFanOut::Where() const {
  std::vector<std::string> lines;
  for (const Adapter& a : adapters_) lines.push_back(a.where);
  return lines;
}

}  // namespace mocap::service

// The streams of `serve`, wired to the service: the own UDP stream, OSC, the Qualisys RT,
// NatNet and VRPN servers and VMC (each off unless asked), made from serve's options and the
// stream options, every one subscribed to the hub's frames (each frame shared once,
// stream/shared_frame.h, and queued to every adapter), to its captures' start and stop
// (pipeline/capture_event.h: the Qualisys RT server tells its clients) and carried in
// /api/status under its name (stream, osc, qtm_rt, natnet, vrpn, vmc). `serve` only makes one.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "service/hub_service.h"
#include "service/serve_options.h"
#include "stream/natnet/natnet_server.h"
#include "stream/shared_frame.h"
#include "stream/stream_sink.h"
#include "stream/udp_stream_server.h"
#include "stream/vrpn/vrpn_server.h"

namespace mocap::service {

// The streams asked for, as `serve`'s command line and hub.conf give them.
struct StreamsOptions {
  stream::UdpStreamOptions stream;        // listen "off": none
  std::string stream_multicast_parts = "points,bodies";
  std::string osc_targets;                // comma-separated HOST:PORT; empty: off
  std::string osc_parts = "points,bodies";
  std::string qtm_rt;                     // HOST:PORT of the Qualisys RT server; empty: off
  stream::natnet::NatNetOptions natnet;   // listen empty: off
  bool natnet_unicast = false;            // frames to each connected client (multicast cleared)
  stream::vrpn::VrpnOptions vrpn;         // listen empty: off
  std::string vmc;                        // HOST:PORT of a VMC receiver; empty: off

  StreamsOptions() {
    natnet.listen.clear();
    vrpn.listen.clear();
  }
  // Throws std::invalid_argument naming the bad option; `serve` gives the rate.
  void Check(const ServeOptions& serve) const;
};

class StreamFanOut {
 public:
  // Starts the streams asked for: throws std::invalid_argument as Check, std::runtime_error when
  // one cannot listen or a file it reads (calibration, bodies, marker set) cannot be read. `also`
  // (if set) gets every shared frame right after the own UDP stream (serve's WebSockets).
  StreamFanOut(const ServeOptions& serve, const StreamsOptions& options, HubService& hub,
               std::function<void(stream::SharedFrame)> also = nullptr);
  ~StreamFanOut();
  StreamFanOut(const StreamFanOut&) = delete;
  StreamFanOut& operator=(const StreamFanOut&) = delete;

  // One line per stream saying where it is, for the log (tests read the ports from them).
  std::vector<std::string> Where() const;

 private:
  struct Adapter {
    std::string name;  // its /api/status section
    std::unique_ptr<stream::StreamSink> sink;
    std::string where;  // the log line saying where it is
  };
  void Publish(const pipeline::LiveFrame& frame);
  void Add(std::string name, std::unique_ptr<stream::StreamSink> sink, std::string where);
  void AddTrackers(const ServeOptions& serve);

  StreamsOptions options_;
  HubService& hub_;
  std::function<void(stream::SharedFrame)> also_;
  std::vector<Adapter> adapters_;  // the own UDP stream first when on: it may send at once
  int frames_id_ = 0;
  int captures_id_ = 0;
};

}  // namespace mocap::service

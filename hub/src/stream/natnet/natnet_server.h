// The NatNet server of `mocap-hub serve --natnet HOST:PORT` (Motive's command port, 1510 by
// default): clients send their requests there (natnet_commands.h answers them); frames go to the
// multicast group (239.255.42.99:1511 by default, as Motive) or, with --natnet-unicast, to every
// client that connected, at the address it sent from (its command socket, where NatNet SDK
// clients read unicast frames), for as long as it keeps sending (any request or NAT_KEEPALIVE
// within `client_timeout_s`).
//
// Threads: Publish() (the hub's loop) encodes each frame once and hands it to the kernel for the
// group or every client at once (non-blocking sends, no thread hand-over) when the frames go to
// the group or to at most `inline_clients` clients and the server's own thread is not answering
// requests at that moment; otherwise it queues the shared frame for that thread, which runs a
// poll() loop over the socket and a wake-up eventfd, answers requests and sends what was queued
// (queued frames always go before a newer one). The time from the hub's publish to the last
// send is sampled (stats publish_to_sent_ms). Errors: the constructor throws
// std::invalid_argument for bad options and std::runtime_error when it cannot bind; nothing a
// client sends throws (bad requests are answered and counted).
#pragma once

#include <netinet/in.h>

#include <atomic>
#include <cstdint>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "ingest/udp_socket.h"
#include "stream/polled_frame_queue.h"
#include "stream/stream_sink.h"
#include "stream/natnet/natnet_commands.h"
#include "stream/publish_latency.h"

namespace mocap::stream::natnet {

struct NatNetOptions {
  std::string listen = "0.0.0.0:1510";     // the command port; port 0 picks a free one
  std::string multicast = "239.255.42.99";  // frames' group; empty: unicast to connected clients
  uint16_t data_port = 1511;                // the group's port (NAT_SERVERINFO tells clients)
  int multicast_ttl = 1;
  std::string version = "4.1";              // bitstream version until a client asks another
  size_t max_clients = 256;                 // unicast subscribers; more are told so
  double client_timeout_s = 10.0;           // unicast: silence this long ends a subscription
  size_t queue_frames = 64;
  size_t inline_clients = 8;                // unicast: up to this many, sent on the hub's loop

  void Check() const;  // throws std::invalid_argument naming the option
};

struct NatNetStats {
  size_t clients = 0;            // unicast subscribers now
  uint64_t requests = 0;
  uint64_t refused = 0;          // failed commands, malformed or unknown requests, clients over max
  uint64_t frames = 0;           // frames sent (to the group or anyone)
  uint64_t frames_on_publish = 0;  // of those, sent on the hub's loop as they were published
  uint64_t datagrams = 0;
  uint64_t send_failures = 0;
  uint64_t frames_dropped = 0;   // this thread fell behind the hub
  uint64_t points_dropped = 0;   // left out to fit a datagram
};

class NatNetServer : public StreamSink {
 public:
  NatNetServer(NatNetOptions options, Model model);
  ~NatNetServer() override;
  NatNetServer(const NatNetServer&) = delete;
  NatNetServer& operator=(const NatNetServer&) = delete;

  uint16_t port() const { return socket_.port(); }
  void Publish(SharedFrame frame) override;
  NatNetStats stats() const;
  nlohmann::json StatsJson() const override;

 private:
  struct Client {
    sockaddr_in address{};
    uint64_t last_seen_ns = 0;
  };

  void Run();
  void Serve(uint64_t now_ns);
  void Subscribe(const sockaddr_in& from, Subscription what, uint64_t now_ns);
  void SendQueued();
  void Send(const pipeline::LiveFrame& frame, bool on_publish);
  std::string EncodeLatest(uint64_t* points_dropped);

  const NatNetOptions options_;
  const Model model_;
  UdpSocket socket_;
  bool multicast_ = false;
  sockaddr_in group_{};
  std::mutex send_mutex_;        // the socket, state_, clients_ and latest_: the thread's or Publish()'s
  CommandState state_;
  std::vector<Client> clients_;
  SharedFrame latest_;
  PolledFrameQueue queue_;
  mutable std::mutex stats_mutex_;
  NatNetStats stats_;
  PublishLatency latency_;  // under stats_mutex_
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

}  // namespace mocap::stream::natnet

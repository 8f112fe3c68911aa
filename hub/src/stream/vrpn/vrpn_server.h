// The VRPN tracker server of `mocap-hub serve --vrpn HOST:PORT` (3883 by default): every rigid
// body of the bodies file is a vrpn_Tracker named after it (sensor 0), reporting its pose
// (metres, quaternion) whenever it is fitted, time-stamped with the frame's trigger time (the
// capture time on the session clock), and with --vrpn-velocity its velocity from the last two
// fitted poses. vrpn_protocol.h has the protocol.
//
// Clients reach it both ways VRPN clients do: "tcp://HOST:PORT" connects to the TCP port; a
// plain "Tracker@HOST:PORT" sends a UDP datagram "<its IP> <its TCP port>" to the same port
// number and waits for the server to connect back. A lookup is honoured only when the IP it names
// is the address it came from (nobody can make the hub connect to a third host), once per
// address and port at a time.
//
// Threads: Publish() (the hub's loop) encodes each frame's reports once and hands them to every
// client's socket at once (non-blocking sends, no thread hand-over) when at most
// `inline_clients` are connected and the server's own thread is not busy with the clients at
// that moment; otherwise it queues the shared frame for that thread, which runs a poll() loop
// over the sockets, every client and a wake-up eventfd, and sends what was queued (queued frames
// always go before a newer one). The time from the hub's publish to the last client's bytes
// handed to the kernel is sampled (stats publish_to_sent_ms). Slow clients: a client's
// queued bytes are bounded; a frame that does not fit is dropped for that client only (whole
// frames), a client that does not take even its answers is closed. Errors: the constructor
// throws std::invalid_argument for bad options and std::runtime_error when it cannot listen;
// nothing a client sends throws.
#pragma once

#include <netinet/in.h>

#include <atomic>
#include <cstdint>
#include <deque>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "stream/polled_frame_queue.h"
#include "stream/stream_sink.h"
#include "stream/vrpn/vrpn_protocol.h"
#include "stream/publish_latency.h"

namespace mocap::stream::vrpn {

struct VrpnOptions {
  std::string listen = "0.0.0.0:3883";  // TCP and UDP lookup; port 0 picks a free one (the same for both)
  bool velocity = false;                // also vrpn_Tracker Velocity reports
  size_t max_clients = 128;
  size_t client_frame_bytes = 64 * 1024;       // queued beyond this: the frame drops for that client
  size_t client_reply_bytes = 1024 * 1024;     // unread answers beyond this close the client
  size_t queue_frames = 64;
  size_t inline_clients = 8;                   // up to this many clients: sent on the hub's loop

  void Check() const;  // throws std::invalid_argument naming the option
};

struct VrpnStats {
  size_t clients = 0;
  uint64_t connections = 0;     // cookies exchanged
  uint64_t lookups = 0;         // UDP connection requests honoured
  uint64_t refused = 0;         // bad cookies or messages, lookups for another host, over max_clients
  uint64_t frames = 0;
  uint64_t frames_on_publish = 0;  // of those, sent on the hub's loop as they were published
  uint64_t reports = 0;         // tracker messages queued to clients
  uint64_t frames_dropped = 0;  // a slow client's, and this thread falling behind the hub
};

class VrpnServer : public StreamSink {
 public:
  // trackers: the rigid bodies' names in the bodies file's order (LiveBody id - 1).
  VrpnServer(VrpnOptions options, std::vector<std::string> trackers);
  ~VrpnServer() override;
  VrpnServer(const VrpnServer&) = delete;
  VrpnServer& operator=(const VrpnServer&) = delete;

  uint16_t port() const { return port_; }
  void Publish(SharedFrame frame) override;
  VrpnStats stats() const;
  nlohmann::json StatsJson() const override;

 private:
  struct Client;
  struct LastPose {
    bool valid = false;
    uint64_t time_ns = 0;
    Eigen::Vector3d position = Eigen::Vector3d::Zero();
    Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();
  };

  void Run();
  void Accept();
  void Lookups();
  void Read(Client& c);
  void Queue(Client& c, std::shared_ptr<const std::string> bytes, bool droppable);
  void Flush(Client& c);
  void SendQueued();
  void SendFrame(const pipeline::LiveFrame& frame, bool on_publish);
  void CloseDead();

  const VrpnOptions options_;
  const std::vector<std::string> trackers_;
  int listen_fd_ = -1;
  int udp_fd_ = -1;
  uint16_t port_ = 0;
  std::mutex clients_mutex_;  // clients_ and last_: the thread's, or Publish()'s when it sends
  std::vector<std::unique_ptr<Client>> clients_;
  std::vector<LastPose> last_;
  PolledFrameQueue queue_;
  mutable std::mutex stats_mutex_;
  VrpnStats stats_;
  PublishLatency latency_;  // under stats_mutex_
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

}  // namespace mocap::stream::vrpn

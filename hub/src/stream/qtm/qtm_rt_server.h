// The Qualisys-RT-compatible server of `mocap-hub serve` (--qtm-rt HOST:PORT): the protocol's
// little-endian TCP port. Clients connect, get "QTM RT Interface connected", negotiate a
// version, read parameters (XML) and poll or stream frames over their TCP connection or over
// UDP (rt_session.h has the protocol, rt_frame.h how the hub's result maps onto it).
//
// Threads: one thread of its own runs a poll() loop over the listening socket, every client and
// a wake-up eventfd; Publish() (the hub's loop) only queues the shared frame and wakes it.
// Events: Connected when frames start to flow, Connection Closed when none came for
// `silence_s` (both: the hub's camera system as QTM reports its own), Capture Started / Stopped
// when the hub's capture (mocap-hub capture start/stop) does (OnCapture, the hub's event), QTM Shutting Down when the server
// stops.
// Slow consumers: a client's queued bytes are bounded; a streamed frame that does not fit is
// dropped for that client only (whole frames), a client that does not even read its answers is
// closed. Errors: the constructor throws std::invalid_argument for bad options and
// std::runtime_error when it cannot listen; nothing a client sends throws.
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "stream/polled_frame_queue.h"
#include "stream/stream_sink.h"
#include "stream/qtm/rt_session.h"

namespace mocap::stream::qtm {

struct QtmRtOptions {
  std::string listen;                       // HOST:PORT; port 0 picks a free one
  size_t max_clients = 128;                 // more are told so and closed (as QTM does)
  // A client's queue beyond which streamed frames drop: about 0.25 s of 60 markers at 240 Hz
  // with residuals; more would only hand a slow client stale frames.
  size_t client_frame_bytes = 64 * 1024;
  size_t client_reply_bytes = 4 * 1024 * 1024;  // unread answers beyond this close the client
  // The kernel's send buffer per client (SO_SNDBUF; Linux doubles it): fixed rather than
  // autotuned up to megabytes, so a client that does not read holds little memory and little
  // stale data.
  int client_socket_bytes = 64 * 1024;
  size_t queue_frames = 64;                 // frames between the hub's loop and this thread
  double silence_s = 1.0;                   // no frame this long: Connection Closed

  // Throws std::invalid_argument naming the bad option.
  void Check() const;
};

struct QtmRtStats {
  size_t clients = 0;
  uint64_t connections = 0;       // accepted since start
  uint64_t refused = 0;           // over max_clients
  uint64_t frames = 0;            // frames received from the hub
  uint64_t packets_sent = 0;      // data packets queued to clients (TCP) or sent (UDP)
  uint64_t frames_dropped = 0;    // streamed frames a slow client did not get
  uint64_t queue_dropped = 0;     // frames this thread fell behind the hub by
  uint64_t errors = 0;            // error answers (bad commands, bad packets)
  uint64_t udp_failures = 0;      // datagrams the kernel refused
};

// What the server tells clients about the system: serve's rate and the calibration's cameras
// (their up direction gives AxisUpwards). Throws std::runtime_error if the file cannot be read.
RtSystem LoadRtSystem(const std::string& calibration_path, double rate_hz, const std::string& bodies_file = "",
                      const std::string& labels_file = "");

class QtmRtServer : public StreamSink {
 public:
  QtmRtServer(QtmRtOptions options, RtSystem system);
  ~QtmRtServer() override;
  QtmRtServer(const QtmRtServer&) = delete;
  QtmRtServer& operator=(const QtmRtServer&) = delete;

  uint16_t port() const { return port_; }
  void Publish(SharedFrame frame) override;
  // The hub's capture started or stopped: clients hear Capture Started / Stopped (the server's
  // thread sends it; this only records the state and wakes it).
  void OnCapture(const pipeline::CaptureEvent& event) override;
  QtmRtStats stats() const;
  nlohmann::json StatsJson() const override;

 private:
  struct Client;

  void Run();
  void Accept();
  void Read(Client& client);
  void Deliver(Client& client, RtOutput& out);
  void Flush(Client& client);
  void TakeFrames();
  void Broadcast(RtEvent event);
  void CloseDead();
  void TakeCaptureState();

  const QtmRtOptions options_;
  int listen_fd_ = -1;
  int udp_fd_ = -1;
  uint16_t port_ = 0;
  PolledFrameQueue queue_;
  RtServerState state_;  // the thread's own
  std::vector<std::unique_ptr<Client>> clients_;
  uint64_t last_frame_ns_ = 0;  // steady clock
  mutable std::mutex stats_mutex_;
  QtmRtStats stats_;
  std::atomic<bool> stop_{false};
  std::atomic<int> capture_state_{0};  // from OnCapture: 0 none heard yet, 1 idle, 2 capturing
  std::thread thread_;
};

}  // namespace mocap::stream::qtm

// The project's own stream over UDP: clients subscribe by sending a StreamRequest to the
// stream port (and renew it every second), after proving their address with the cookie of the
// hub's challenge (subscription_guard.h: a forged source gets nothing sent to it); every published frame goes to each subscriber as
// one StreamFrame datagram with the parts it asked for, and to the multicast group when one is
// configured. With few subscribers (`inline_subscribers`) the hub's loop encodes and sends at
// once (a few tens of microseconds, one thread hand-over less on the way to the client); with
// more, its own thread does, and the loop only queues the shared frame. A send that would block
// is dropped for that subscriber (a slow client loses its own frames).
//
// Threads: Publish() from the hub's loop; stats() from any thread. Errors: the constructor
// throws std::invalid_argument for bad options and std::runtime_error when it cannot bind;
// bad requests from clients are counted, never thrown.
#pragma once

#include <atomic>
#include <cstdint>
#include <mutex>
#include <string>
#include <thread>

#include <nlohmann/json_fwd.hpp>

#include "ingest/udp_socket.h"
#include "stream/frame_queue.h"
#include "stream/stream_sink.h"
#include "stream/stream_encoding.h"
#include "stream/subscriber_table.h"
#include "stream/subscription_guard.h"
#include "stream/publish_latency.h"

namespace mocap::stream {

struct UdpStreamOptions {
  std::string listen = "0.0.0.0:7802";   // subscription requests arrive here; frames leave from it
  std::string multicast;                 // "GROUP:PORT" (e.g. 239.255.42.1:7803); empty: none
  uint32_t multicast_parts = kDefaultParts;
  int multicast_ttl = 1;
  size_t max_subscribers = 256;
  double subscription_s = 5.0;
  size_t queue_frames = 64;             // frames waiting for the sending thread (oldest dropped)
  size_t inline_subscribers = 8;         // up to this many (multicast counts as one): sent inline
  SubscriptionGuardOptions guard;        // cookies and per-source request rates

  // Throws std::invalid_argument naming the bad option.
  void Check() const;
};

struct UdpStreamStats {
  size_t subscribers = 0;
  uint64_t frames = 0;               // frames sent (to anyone)
  uint64_t datagrams = 0;            // datagrams sent
  uint64_t send_failures = 0;        // a subscriber's socket would block or is gone
  uint64_t frames_dropped = 0;       // the sending thread fell behind the hub
  uint64_t bad_requests = 0;         // malformed or refused subscription requests
  uint64_t challenges = 0;           // cookies sent to an address not yet proven
  uint64_t unproven = 0;             // requests with a missing, wrong or stale cookie
  uint64_t rate_limited = 0;         // requests over their source's rate, dropped unanswered
  uint64_t points_dropped = 0;       // points left out to fit a datagram
};

class UdpStreamServer : public StreamSink {
 public:
  explicit UdpStreamServer(UdpStreamOptions options);
  ~UdpStreamServer() override;
  UdpStreamServer(const UdpStreamServer&) = delete;
  UdpStreamServer& operator=(const UdpStreamServer&) = delete;

  uint16_t port() const { return socket_.port(); }
  void Publish(SharedFrame frame) override;
  UdpStreamStats stats() const;
  nlohmann::json StatsJson() const override;

 private:
  void Run();
  void ServeRequests(uint64_t now_ns);
  void Send(const pipeline::LiveFrame& frame);

  const UdpStreamOptions options_;
  UdpSocket socket_;
  bool has_multicast_ = false;
  sockaddr_in multicast_{};
  FrameQueue queue_;
  std::mutex table_mutex_;  // table_, and one sender at a time
  SubscriberTable table_;
  SubscriptionGuard guard_;
  mutable std::mutex stats_mutex_;
  UdpStreamStats stats_;
  PublishLatency latency_;  // under stats_mutex_
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

}  // namespace mocap::stream

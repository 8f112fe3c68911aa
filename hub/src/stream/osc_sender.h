// OSC output (liblo from Debian): every published frame as one OSC bundle to each configured
// target, for VR, game engines, show control and patchers (Max, Pure Data, TouchDesigner).
// The address space (documented in docs/streams.md; millimetres, world frame):
//   /mocap/frame      h:frame_number h:trigger_time_ns i:points i:bodies
//   /mocap/marker     i:track f:x f:y f:z f:residual_px i:views      (confirmed)
//   /mocap/point      h:track f:x f:y f:z f:residual_px i:views      (provisional; -1: none)
// track: the track's id (the stream's id), the same number from its first frame as a point to
// its frames as a confirmed marker (an id past 2^31 - 1 wraps to 1 in /mocap/marker's int32).
//   /mocap/rigidbody  s:name f:x f:y f:z f:qx f:qy f:qz f:qw f:mean_error_mm   (tracked bodies)
// With the part bones (serve --skeleton), per skeleton and then per bone when solved:
//   /mocap/skeleton   s:name i:solved s:state i:markers f:rms_mm f:max_mm
//   /mocap/bone       s:skeleton s:bone i:parent f:x f:y f:z f:qx f:qy f:qz f:qw   (joint centre,
//                     segment -> world; parent: the bone's index in the skeleton, -1 for the root)
// /mocap/frame comes first in its bundle. A bundle holds at most kMaxOscPoints points (the
// rest are counted as dropped: one UDP datagram per frame). Its own thread builds and sends, so
// the hub's loop only queues a shared frame.
//
// Threads: Publish() from the hub's loop, stats() from any. Errors: the constructor throws
// std::invalid_argument for a bad target or part list; failed sends are counted.
#pragma once

#include <atomic>
#include <cstdint>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "stream/frame_queue.h"
#include "stream/stream_sink.h"
#include "stream/stream_encoding.h"

namespace mocap::stream {

constexpr size_t kMaxOscPoints = 1000;

struct OscOptions {
  std::vector<std::string> targets;   // HOST:PORT each (unicast, broadcast or multicast)
  uint32_t parts = kDefaultParts;     // points, bodies and/or bones
  int ttl = 1;                        // for multicast targets
  size_t queue_frames = 64;           // frames between the hub's loop and the sending thread

  void Check() const;  // throws std::invalid_argument
};

struct OscStats {
  uint64_t bundles = 0;
  uint64_t send_failures = 0;
  uint64_t frames_dropped = 0;
  uint64_t points_dropped = 0;
};

// The messages of one frame's bundle, in order (path, OSC type tags): what the sender builds,
// exposed so tests can check the address space without a network.
struct OscMessageShape {
  std::string path;
  std::string types;
};
std::vector<OscMessageShape> OscBundleShape(const pipeline::LiveFrame& frame, uint32_t parts);

class OscSender : public StreamSink {
 public:
  explicit OscSender(OscOptions options);
  ~OscSender() override;
  OscSender(const OscSender&) = delete;
  OscSender& operator=(const OscSender&) = delete;

  void Publish(SharedFrame frame) override { queue_.Push(std::move(frame)); }
  OscStats stats() const;
  nlohmann::json StatsJson() const override;

 private:
  struct Targets;
  void Run();

  const OscOptions options_;
  std::unique_ptr<Targets> targets_;
  FrameQueue queue_;
  mutable std::mutex stats_mutex_;
  OscStats stats_;
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

}  // namespace mocap::stream

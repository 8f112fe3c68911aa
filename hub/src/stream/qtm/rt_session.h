// One client of the Qualisys RT server as a state machine without sockets: bytes in, packets
// out. It frames the client's bytes (rt_packet.h), answers commands (rt_command.h) with command,
// error, XML or event packets, and keeps the client's stream settings (rate, components, TCP or
// UDP) so the server can ask, frame by frame, what this client gets.
//
// Answers to commands are never dropped; streamed frames are marked droppable so a server can
// shed them for a client that does not read (the client then misses whole frames, never parts).
// Pure code: no I/O, no clock.
#pragma once

#include <netinet/in.h>

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "stream/qtm/rt_command.h"
#include "stream/qtm/rt_frame.h"
#include "stream/qtm/rt_packet.h"
#include "stream/qtm/rt_parameters.h"
#include "stream/shared_frame.h"

namespace mocap::stream::qtm {

using PacketPtr = std::shared_ptr<const std::string>;

// What every session reads: owned by the server's thread and updated there before sessions see
// a frame.
struct RtServerState {
  RtSystem system;
  RtNames names;
  SharedFrame latest;     // the newest frame, null before the first
  bool flowing = false;   // frames arrive (Connected) or stopped (Connection Closed)
  bool capturing = false;  // the hub records a capture (Capture Started / Stopped)
  std::string server_version = "mocap-hub";

  // What GetState reports: a running capture, else whether frames flow.
  RtEvent State() const {
    if (capturing) return RtEvent::kCaptureStarted;
    return flowing ? RtEvent::kConnected : RtEvent::kConnectionClosed;
  }
};

struct RtOutPacket {
  PacketPtr bytes;
  bool droppable = false;  // a streamed frame
};

struct RtOutput {
  std::vector<RtOutPacket> tcp;    // in order
  std::vector<PacketPtr> udp;      // to udp_target()
  bool close = false;              // close once `tcp` is sent
};

// Encodes `frame` with a component mask once per frame for every client asking the same.
using RtEncoder = std::function<PacketPtr(uint32_t components)>;

class RtSession {
 public:
  // peer: the client's address (UDP streams without an address go there). Queues the greeting.
  RtSession(const sockaddr_in& peer, RtOutput* out);

  // Bytes from the client. Stop once out->close is set.
  void Receive(const uint8_t* data, size_t size, const RtServerState& state, RtOutput* out);
  // A new frame (state.latest is it): a stream gets it when its rate says so.
  void OnFrame(const RtServerState& state, const RtEncoder& encode, RtOutput* out);
  // A state event for every client; frames stopping also ends each stream's data with a No
  // More Data packet (the protocol's "measurement stopped").
  void OnEvent(RtEvent event, RtOutput* out);

  bool streaming() const { return streaming_; }
  const sockaddr_in& udp_target() const { return udp_target_; }
  uint64_t errors() const { return errors_; }

 private:
  void HandlePacket(const ReceivedPacket& packet, const RtServerState& state, RtOutput* out);
  void HandleCommand(const Command& command, const RtServerState& state, RtOutput* out);
  void Reply(RtOutput* out, PacketType type, const std::string& text);
  bool RateTakes(double rate_hz);

  sockaddr_in peer_{};
  PacketReader reader_;
  int version_minor_ = 1;  // the protocol's default until the client sends Version
  uint64_t errors_ = 0;

  bool streaming_ = false;
  uint32_t stream_components_ = 0;
  FrameRate rate_ = FrameRate::kAllFrames;
  uint32_t rate_value_ = 0;
  uint64_t divisor_count_ = 0;
  uint64_t frequency_seen_ = 0;
  uint64_t frequency_sent_ = 0;
  bool udp_ = false;
  sockaddr_in udp_target_{};
};

}  // namespace mocap::stream::qtm

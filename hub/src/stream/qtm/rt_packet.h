// Packets of the Qualisys RT protocol (little-endian port): an 8-byte header (total size, type)
// and a body. The reader cuts a TCP byte stream from a client into whole packets with bounded
// memory: a packet too large to be a command is skipped without being buffered, and a header
// that cannot be a packet at all ends the connection (nothing after it can be framed again).
// Pure code: no I/O, no clock.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

#include "util/little_endian.h"

namespace mocap::stream::qtm {

enum class PacketType : uint32_t {
  kError = 0,
  kCommand = 1,
  kXml = 2,
  kData = 3,
  kNoMoreData = 4,
  kC3dFile = 5,
  kEvent = 6,
  kDiscover = 7,
  kQtmFile = 8,
};

// Events (one byte in an event packet); the ones the hub raises (qtm_rt_server.h says when).
enum class RtEvent : uint8_t {
  kConnected = 1,
  kConnectionClosed = 2,
  kCaptureStarted = 3,
  kCaptureStopped = 4,
  kQtmShuttingDown = 12,
};

constexpr size_t kHeaderSize = 8;
// The largest packet a client may send that is still answered (a command line or an XML
// settings document); larger ones are skipped with an error answer.
constexpr size_t kMaxCommandPacket = 16 * 1024;
// Anything claiming more than this is not a packet of this protocol: the connection is closed.
constexpr size_t kMaxFramedPacket = 1024 * 1024;

using le::GetU32;
using le::PutF32;
using le::PutU16;
using le::PutU32;
using le::PutU64;

// A whole packet: header + body.
std::string MakePacket(PacketType type, const std::string& body);
// Command, error and XML packets carry a NUL-terminated string.
std::string MakeStringPacket(PacketType type, const std::string& text);
std::string MakeEventPacket(RtEvent event);

struct ReceivedPacket {
  uint32_t type = 0;
  std::string body;      // empty when skipped
  bool too_large = false;  // the body exceeded kMaxCommandPacket and was discarded
};

class PacketReader {
 public:
  // Consumes up to `size` bytes; returns how many were used (the rest waits for a Next()).
  // Stop feeding once broken().
  size_t Feed(const uint8_t* data, size_t size);
  // One complete packet, if there is one (call until false after each Feed).
  bool Next(ReceivedPacket* packet);
  // A header that cannot start a packet: size < 8 or > kMaxFramedPacket.
  bool broken() const { return broken_; }
  uint32_t broken_size() const { return broken_size_; }
  // Bytes held right now (bounded by kHeaderSize + kMaxCommandPacket).
  size_t buffered() const { return header_fill_ + body_.size(); }

 private:
  uint8_t header_[kHeaderSize] = {};
  size_t header_fill_ = 0;
  bool in_body_ = false;
  uint32_t size_ = 0;
  uint32_t type_ = 0;
  size_t body_seen_ = 0;
  std::string body_;
  bool ready_ = false;
  ReceivedPacket pending_;
  bool broken_ = false;
  uint32_t broken_size_ = 0;
};

}  // namespace mocap::stream::qtm

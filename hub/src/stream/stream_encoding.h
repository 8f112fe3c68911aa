// The project's own stream (proto/mocap_stream.proto): a published frame -> the StreamFrame a
// subscriber asked for, and a subscriber's request <- the bytes it sent. Pure: no sockets, no
// clock. Outside input (requests) never throws: a bad request comes back with its reason.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

#include "pipeline/live_frame.h"

namespace mocap::stream {

// proto/mocap_stream.proto Part bits.
constexpr uint32_t kPartPoints = 1;
constexpr uint32_t kPartBodies = 2;
constexpr uint32_t kPartLabels = 4;
constexpr uint32_t kPartBones = 8;
constexpr uint32_t kAllParts = kPartPoints | kPartBodies | kPartLabels | kPartBones;
constexpr uint32_t kDefaultParts = kPartPoints | kPartBodies;

constexpr uint32_t kStreamVersion = 1;
// A UDP datagram's payload (IPv4 limit 65507) with room to spare.
constexpr size_t kMaxStreamMessage = 65000;
// A request is a few bytes; anything longer is not one.
constexpr size_t kMaxStreamRequest = 64;

// The StreamFrame of `frame` with `parts`, serialised. Points that would take the message over
// max_bytes are left out (the last ones) and counted in points_dropped; the caller's limit
// must leave room for the header and the bodies.
struct EncodedFrame {
  std::string bytes;
  uint32_t points_dropped = 0;
};
EncodedFrame EncodeStreamFrame(const pipeline::LiveFrame& frame, uint32_t parts,
                               size_t max_bytes = kMaxStreamMessage);

// A subscription cookie (subscribe_cookie, Subscribe.cookie) is at most this long; a first
// Subscribe is padded to at least kMinFirstRequest bytes, which no challenge exceeds.
constexpr size_t kMaxStreamCookie = 32;
constexpr size_t kMinFirstRequest = 32;

struct StreamRequest {
  bool ok = false;
  std::string reason;          // why not, when !ok
  bool subscribe = false;      // else unsubscribe
  uint32_t parts = 0;          // with subscribe: never 0 (0 asks for kDefaultParts)
  std::string cookie;          // empty when the request carries none
};
StreamRequest DecodeStreamRequest(const uint8_t* data, size_t size);

// The bytes of a request (clients and tests): a first Subscribe (no cookie) is padded to
// kMinFirstRequest bytes.
std::string EncodeSubscribe(uint32_t parts, const std::string& cookie = "");
std::string EncodeUnsubscribe(const std::string& cookie = "");
// The hub's challenge: a StreamFrame holding only subscribe_cookie.
std::string EncodeChallenge(const std::string& cookie);

// "points,bodies,labels,bones" -> Part bits; throws std::invalid_argument naming an unknown part.
uint32_t ParseParts(const std::string& text);

}  // namespace mocap::stream

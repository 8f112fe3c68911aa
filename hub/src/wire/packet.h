// Decoding, validation and encoding of single protocol-v1 datagrams (libprotobuf side).
// Error policy: decoding outside input never throws; it returns a reason. Encoding a packet that
// breaks the wire rules is a programming error and throws std::invalid_argument.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "mocap.pb.h"

namespace mocap::wire {

struct DecodeResult {
  bool ok = false;
  std::string reason;  // why the datagram was rejected; empty when ok
  v1::Packet packet;
};

// Parses and validates one datagram.
DecodeResult Decode(const uint8_t* data, size_t size);

// Empty when the packet obeys every v1 rule, otherwise the first broken rule.
std::string Validate(const v1::Packet& packet);

// Serializes a valid packet (deterministic field order) and checks the 1352-byte packet limit
// (the envelope brings the datagram to at most 1400).
std::vector<uint8_t> Encode(const v1::Packet& packet);

// The hub's HubAnnounce datagram: where nodes send (port), frame 0's time and the trigger rate.
std::vector<uint8_t> EncodeHubAnnounce(uint16_t port, uint64_t epoch_ns, double rate_hz);

uint32_t ToSubpixel(double px);
double FromSubpixel(uint32_t q);

}  // namespace mocap::wire

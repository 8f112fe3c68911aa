// The authenticated envelope around every hub<->node datagram, hub side: pure sealing, parsing
// and tag checking with libsodium's crypto_auth (HMAC-SHA-512/256). The layout is the
// firmware's (firmware/wire/envelope.h), byte for byte; tests/golden/envelope_* prove it:
//   0 u8 magic 0xA1 | 1 u8 direction (0 node->hub, 1 hub->node) | 2 u8 key id 1..255 |
//   3 u8 reserved 0 | 4 u32 node id | 8 u64 counter | 16 payload (one Packet) | tag[32]
// (little-endian), the tag covering every byte before it. Why HMAC rather than an AEAD, the
// counters and the replay window: wire README (hub/src/wire/README.md).
// Error policy: parsing outside input never throws (it returns a reason); sealing a header or
// payload that breaks the layout is a programming error and throws std::invalid_argument.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace mocap::wire {

constexpr uint8_t kEnvelopeMagic = 0xA1;
constexpr size_t kEnvelopeHeaderBytes = 16;
constexpr size_t kEnvelopeTagBytes = 32;
constexpr size_t kEnvelopeOverheadBytes = kEnvelopeHeaderBytes + kEnvelopeTagBytes;
constexpr size_t kWireKeyBytes = 32;
// A counter further than this from the receiver's clock is refused (firmware: the same value).
constexpr uint64_t kMaxCounterSkewNs = 2'000'000'000;

using WireKey = std::array<uint8_t, kWireKeyBytes>;

enum class Direction : uint8_t { kToHub = 0, kToNode = 1 };

struct EnvelopeHeader {
  Direction direction = Direction::kToHub;
  uint8_t key_id = 1;
  uint32_t node_id = 0;
  uint64_t counter = 0;
};

struct ParsedEnvelope {
  bool ok = false;
  std::string reason;             // why not, when !ok
  EnvelopeHeader header;
  const uint8_t* payload = nullptr;  // inside the parsed datagram
  size_t payload_size = 0;
};

// Starts libsodium (once; thread-safe). Throws std::runtime_error if it cannot.
void InitSodium();

// True when the datagram claims to be an envelope (its first byte), false for a plain packet.
inline bool LooksEnveloped(const uint8_t* data, size_t size) { return size > 0 && data[0] == kEnvelopeMagic; }

// Reads and checks the header and sizes; never the tag.
ParsedEnvelope ParseEnvelope(const uint8_t* data, size_t size);
// The tag of data[0..size) under key, in constant time.
bool VerifyEnvelopeTag(const uint8_t* data, size_t size, const WireKey& key);
// header + payload + tag.
std::vector<uint8_t> SealEnvelope(const EnvelopeHeader& header, const WireKey& key, const uint8_t* payload,
                                  size_t payload_size);
// The sender's next counter: now_ns, or last + 1 when the clock has not moved past it.
inline uint64_t NextCounter(uint64_t last, uint64_t now_ns) { return now_ns > last ? now_ns : last + 1; }

}  // namespace mocap::wire

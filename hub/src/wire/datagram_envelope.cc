// Authenticated envelope, hub side (see datagram_envelope.h).
#include "wire/datagram_envelope.h"

#include <cstring>
#include <stdexcept>

#include <sodium.h>

#include "wire/limits.h"

namespace mocap::wire {
namespace {

static_assert(kEnvelopeTagBytes == crypto_auth_hmacsha512256_BYTES, "tag size is libsodium's");
static_assert(kWireKeyBytes == crypto_auth_hmacsha512256_KEYBYTES, "key size is libsodium's");
static_assert(kMaxPacketBytes + kEnvelopeOverheadBytes == kMaxDatagramBytes, "the packet budget leaves room");

uint64_t GetLe(const uint8_t* p, int bytes) {
  uint64_t v = 0;
  for (int i = bytes - 1; i >= 0; --i) v = v << 8 | p[i];
  return v;
}

void PutLe(uint8_t* p, uint64_t v, int bytes) {
  for (int i = 0; i < bytes; ++i) p[i] = static_cast<uint8_t>(v >> (8 * i));
}

ParsedEnvelope Refuse(const char* reason) {
  ParsedEnvelope p;
  p.reason = reason;
  return p;
}

}  // namespace

void InitSodium() {
  if (sodium_init() < 0) throw std::runtime_error("libsodium cannot start");
}

ParsedEnvelope ParseEnvelope(const uint8_t* data, size_t size) {
  if (!LooksEnveloped(data, size)) return Refuse("not an authenticated datagram");
  if (size > kMaxDatagramBytes) return Refuse("datagram larger than 1400 bytes");
  if (size < kEnvelopeOverheadBytes + 1) return Refuse("envelope too short");
  if (data[1] > static_cast<uint8_t>(Direction::kToNode)) return Refuse("envelope: unknown direction");
  if (data[2] == 0) return Refuse("envelope: key id 0");
  if (data[3] != 0) return Refuse("envelope: reserved byte not 0");
  ParsedEnvelope p;
  p.header.direction = static_cast<Direction>(data[1]);
  p.header.key_id = data[2];
  p.header.node_id = static_cast<uint32_t>(GetLe(data + 4, 4));
  p.header.counter = GetLe(data + 8, 8);
  if (p.header.node_id == 0) return Refuse("envelope: node id 0");
  if (p.header.counter == 0) return Refuse("envelope: counter 0");
  p.payload = data + kEnvelopeHeaderBytes;
  p.payload_size = size - kEnvelopeOverheadBytes;
  p.ok = true;
  return p;
}

bool VerifyEnvelopeTag(const uint8_t* data, size_t size, const WireKey& key) {
  if (size < kEnvelopeOverheadBytes) return false;
  const size_t body = size - kEnvelopeTagBytes;
  return crypto_auth_hmacsha512256_verify(data + body, data, body, key.data()) == 0;
}

std::vector<uint8_t> SealEnvelope(const EnvelopeHeader& h, const WireKey& key, const uint8_t* payload,
                                  size_t payload_size) {
  if (payload_size == 0 || payload_size > kMaxPacketBytes)
    throw std::invalid_argument("envelope: payload size out of range");
  if (h.key_id == 0 || h.node_id == 0 || h.counter == 0)
    throw std::invalid_argument("envelope: header field out of range");
  std::vector<uint8_t> out(kEnvelopeOverheadBytes + payload_size);
  out[0] = kEnvelopeMagic;
  out[1] = static_cast<uint8_t>(h.direction);
  out[2] = h.key_id;
  out[3] = 0;
  PutLe(out.data() + 4, h.node_id, 4);
  PutLe(out.data() + 8, h.counter, 8);
  std::memcpy(out.data() + kEnvelopeHeaderBytes, payload, payload_size);
  const size_t body = kEnvelopeHeaderBytes + payload_size;
  crypto_auth_hmacsha512256(out.data() + body, out.data(), body, key.data());
  return out;
}

}  // namespace mocap::wire

// libFuzzer target: the hub's envelope parser, tag check and replay window on arbitrary bytes.
// Whatever parses lies within the datagram; re-sealed under the fuzz key it verifies and parses
// back to the same header and payload.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>

#include "wire/datagram_envelope.h"
#include "wire/replay_window.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace mocap::wire;
  static const WireKey key = {1, 2, 3, 4, 5, 6, 7, 8};
  static ReplayWindow window(64);
  static bool ready = (InitSodium(), true);
  (void)ready;
  const ParsedEnvelope p = ParseEnvelope(data, size);
  if (!p.ok) return 0;
  if (p.payload != data + kEnvelopeHeaderBytes || p.payload_size + kEnvelopeOverheadBytes != size) std::abort();
  if (VerifyEnvelopeTag(data, size, key)) window.Accept(p.header.counter, 1'700'000'000'000'000'000ull);
  const std::vector<uint8_t> again = SealEnvelope(p.header, key, p.payload, p.payload_size);
  const ParsedEnvelope back = ParseEnvelope(again.data(), again.size());
  if (again.size() != size || !VerifyEnvelopeTag(again.data(), again.size(), key) || !back.ok ||
      back.header.counter != p.header.counter || back.header.node_id != p.header.node_id ||
      back.header.key_id != p.header.key_id || back.header.direction != p.header.direction ||
      std::memcmp(back.payload, p.payload, p.payload_size) != 0)
    std::abort();
  return 0;
}

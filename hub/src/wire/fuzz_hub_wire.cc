// libFuzzer target: the hub's datagram decoder and chunk assembler on arbitrary bytes.
#include <cstddef>
#include <cstdint>

#include "wire/chunking.h"
#include "wire/packet.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static mocap::wire::ChunkAssembler assembler(64);
  const mocap::wire::DecodeResult result = mocap::wire::Decode(data, size);
  if (result.ok && result.packet.has_marker_frame()) {
    mocap::v1::MarkerFrame frame;
    assembler.Add(result.packet.marker_frame(), &frame);
    if (assembler.pending() > 32) assembler.DiscardBefore(~0ull);
  }
  return 0;
}

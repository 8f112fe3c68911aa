// libFuzzer target: arbitrary bytes from a VRPN client, in arbitrary pieces, through one session
// (cookie, message framing, descriptions, pings). Nothing crashes, and everything the session
// sends back is whole messages.
#include <cstddef>
#include <cstdint>
#include <cstdlib>

#include "stream/vrpn/vrpn_protocol.h"

namespace v = mocap::stream::vrpn;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  v::VrpnSession session({"drone", "wand"});
  std::string out;
  // The first byte cuts the input into pieces of 1-32 bytes: framing must not care.
  const size_t piece = size ? 1 + data[0] % 32 : 1;
  for (size_t at = size ? 1 : 0; at < size && !session.closed(); at += piece)
    session.Receive(data + at, std::min(piece, size - at), at, &out);
  v::MessageReader reader;
  if (reader.Feed(reinterpret_cast<const uint8_t*>(out.data()), out.size()) != out.size() || reader.broken())
    std::abort();
  return 0;
}

// libFuzzer target: arbitrary bytes from an RT client, in arbitrary pieces, through one
// session (framing, command parser, answers), with frames arriving in between. Nothing crashes
// and everything queued for the client is whole packets.
#include <arpa/inet.h>

#include <cstddef>
#include <cstdint>
#include <cstdlib>

#include "stream/qtm/rt_session.h"

namespace q = mocap::stream::qtm;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  q::RtServerState state;
  state.system.rate_hz = 100;
  sockaddr_in peer{};
  peer.sin_family = AF_INET;
  peer.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  q::RtOutput out;
  q::RtSession session(peer, &out);
  auto frame = std::make_shared<mocap::pipeline::LiveFrame>();
  frame->points.resize(3);
  frame->points[1].marker = 2;
  const q::RtEncoder encode = [&](uint32_t c) {
    return std::make_shared<const std::string>(q::EncodeDataPacket(*frame, c, state.names, 2));
  };
  // The first byte cuts the input into pieces of 1-16 bytes: framing must not care.
  const size_t piece = size ? 1 + data[0] % 16 : 1;
  for (size_t at = size ? 1 : 0; at < size && !out.close; at += piece) {
    session.Receive(data + at, std::min(piece, size - at), state, &out);
    if (at % 64 == 1) {
      state.latest = frame;
      state.flowing = true;
      state.names.Update(*frame);
      session.OnFrame(state, encode, &out);
    }
  }
  for (const q::RtOutPacket& p : out.tcp) {
    const std::string& b = *p.bytes;
    if (b.size() < 8 || q::GetU32(reinterpret_cast<const uint8_t*>(b.data())) != b.size()) std::abort();
  }
  return 0;
}

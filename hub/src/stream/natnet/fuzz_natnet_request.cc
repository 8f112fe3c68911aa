// libFuzzer target: an arbitrary datagram to the NatNet command port, parsed and answered with
// the state carried from one input to the next (a Bitstream command changes what later answers
// are written in). Nothing crashes, and every answer is a whole packet whose header tells its size.
#include <cstddef>
#include <cstdint>
#include <cstdlib>

#include "stream/natnet/natnet_commands.h"

namespace n = mocap::stream::natnet;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static n::CommandState state;
  static const n::Model model = [] {
    n::Model m;
    m.rate_hz = 240;
    mocap::RigidBodyDefinition body;
    body.name = "drone";
    body.markers = {{0, 0, 0}, {50, 0, 0}, {0, 40, 0}};
    m.bodies = {body};
    m.label_names = {"a", "b"};
    return m;
  }();
  const n::Request request = n::ParseRequest(data, size);
  const n::Reply reply = n::Answer(request, model, &state);
  if (!n::Supported(state.version)) std::abort();
  const std::string& p = reply.packet;
  if (!p.empty() && (p.size() < 4 || static_cast<size_t>(static_cast<uint8_t>(p[2]) | static_cast<uint8_t>(p[3]) << 8) != p.size() - 4))
    std::abort();
  return 0;
}

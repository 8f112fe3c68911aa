// What the NatNet server answers to one request, as Motive answers it, without sockets:
//   NAT_CONNECT             -> NAT_SERVERINFO (application "mocap-hub", the bitstream version
//                              streamed now, clock 1e9 ticks/s, data port, multicast or not);
//                              in unicast the sender is subscribed to the frames
//   NAT_KEEPALIVE           -> nothing; renews a unicast subscription
//   NAT_DISCONNECT          -> nothing; ends it
//   NAT_REQUEST_MODELDEF    -> NAT_MODELDEF (natnet_frame.h)
//   NAT_REQUEST_FRAMEOFDATA -> the newest frame (the server sends it)
//   NAT_REQUEST "command[,args]" -> NAT_RESPONSE:
//       Bitstream               "Bitstream,<version streamed>"
//       Bitstream,X.Y           0 and every later packet in X.Y (3.0, 3.1, 4.0, 4.1: Motive's
//                               setting is one for all clients), 1 for a version not written
//       UnitsToMillimeters      1000.0 (float: positions are metres)
//       FrameRate               serve's --rate (float)
//       CurrentMode             0 (int: live)
//       LiveMode                0 (already live)
//       anything else           1 (int: failed): the hub has no takes, timeline, recording or
//                               properties to set through NatNet (its captures are driven by
//                               `mocap-hub capture`), and a command it does not know fails too
//   any other message id, or a malformed datagram -> NAT_UNRECOGNIZED_REQUEST
// Command names compare without regard to case. Pure code.
#pragma once

#include <string>

#include "stream/natnet/natnet_frame.h"
#include "stream/natnet/natnet_packet.h"

namespace mocap::stream::natnet {

struct CommandState {
  Version version;   // streamed now
  ServerInfo info;   // what NAT_SERVERINFO says (its version follows `version`)
};

enum class Subscription { kNone, kSubscribe, kKeepAlive, kUnsubscribe };

struct Reply {
  std::string packet;               // to the sender; empty: no answer
  Subscription subscription = Subscription::kNone;
  bool send_frame = false;          // the newest frame to the sender
  bool failed = false;              // refused or malformed (counted by the server)
};

Reply Answer(const Request& request, const Model& model, CommandState* state);

}  // namespace mocap::stream::natnet

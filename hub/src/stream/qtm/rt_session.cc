// One RT client's protocol state (see rt_session.h).
#include "stream/qtm/rt_session.h"

#include <arpa/inet.h>

#include <cmath>

namespace mocap::stream::qtm {
namespace {

PacketPtr Share(std::string bytes) { return std::make_shared<const std::string>(std::move(bytes)); }

}  // namespace

RtSession::RtSession(const sockaddr_in& peer, RtOutput* out) : peer_(peer) {
  Reply(out, PacketType::kCommand, "QTM RT Interface connected");
}

void RtSession::Reply(RtOutput* out, PacketType type, const std::string& text) {
  if (type == PacketType::kError) ++errors_;
  out->tcp.push_back({Share(MakeStringPacket(type, text)), false});
}

void RtSession::Receive(const uint8_t* data, size_t size, const RtServerState& state, RtOutput* out) {
  size_t used = 0;
  while (used < size && !out->close) {
    used += reader_.Feed(data + used, size - used);
    ReceivedPacket packet;
    while (!out->close && reader_.Next(&packet)) HandlePacket(packet, state, out);
    if (reader_.broken()) {
      Reply(out, PacketType::kError,
            "Malformed packet: size " + std::to_string(reader_.broken_size()) + " in header; closing");
      out->close = true;
    }
  }
}

void RtSession::HandlePacket(const ReceivedPacket& packet, const RtServerState& state, RtOutput* out) {
  if (packet.too_large) {
    Reply(out, PacketType::kError, "Command too long (at most " + std::to_string(kMaxCommandPacket) + " bytes)");
    return;
  }
  switch (static_cast<PacketType>(packet.type)) {
    case PacketType::kCommand:
      HandleCommand(ParseCommand(packet.body), state, out);
      return;
    case PacketType::kXml:
      Reply(out, PacketType::kError, "Setting parameters failed: mocap-hub's settings are read-only over RT");
      return;
    default:
      Reply(out, PacketType::kError, "Unexpected packet type " + std::to_string(packet.type));
  }
}

void RtSession::HandleCommand(const Command& c, const RtServerState& state, RtOutput* out) {
  if (!c.ok) {
    Reply(out, PacketType::kError, c.error);
    return;
  }
  switch (c.kind) {
    case CommandKind::kVersion:
      if (c.version_minor) {
        version_minor_ = c.version_minor;
        Reply(out, PacketType::kCommand, "Version set to 1." + std::to_string(version_minor_));
      } else {
        Reply(out, PacketType::kCommand, "Version is 1." + std::to_string(version_minor_));
      }
      return;
    case CommandKind::kQtmVersion:
      Reply(out, PacketType::kCommand, "QTM Version is " + state.server_version + " (Qualisys RT compatible)");
      return;
    case CommandKind::kByteOrder:
      Reply(out, PacketType::kCommand, "Byte order is little endian");
      return;
    case CommandKind::kGetState:
      out->tcp.push_back({Share(MakeEventPacket(state.State())), false});
      return;
    case CommandKind::kGetParameters:
      Reply(out, PacketType::kXml, ParametersXml(state.system, state.names, c.parameters, version_minor_));
      return;
    case CommandKind::kGetCurrentFrame:
      // No frames flowing: the protocol's "no measurement" answer.
      if (state.flowing && state.latest)
        out->tcp.push_back({Share(EncodeDataPacket(*state.latest, c.components, state.names,
                                                   static_cast<int>(state.system.rig.cameras.size()))),
                            false});
      else
        out->tcp.push_back({Share(MakePacket(PacketType::kNoMoreData, "")), false});
      return;
    case CommandKind::kStreamFrames:
      streaming_ = true;
      stream_components_ = c.components;
      rate_ = c.rate;
      rate_value_ = c.rate_value;
      divisor_count_ = 0;
      frequency_seen_ = frequency_sent_ = 0;
      udp_ = c.udp;
      if (udp_) {
        udp_target_ = sockaddr_in{};
        udp_target_.sin_family = AF_INET;
        udp_target_.sin_port = htons(c.udp_port);
        udp_target_.sin_addr = peer_.sin_addr;
        if (!c.udp_address.empty()) inet_pton(AF_INET, c.udp_address.c_str(), &udp_target_.sin_addr);
      }
      // No frames flowing: the protocol's "no measurement" answer, so the client is not left
      // waiting; the stream starts when frames do.
      if (!state.flowing) out->tcp.push_back({Share(MakePacket(PacketType::kNoMoreData, "")), false});
      return;
    case CommandKind::kStreamFramesStop:
      streaming_ = false;
      return;
    case CommandKind::kQuit:
      Reply(out, PacketType::kCommand, "Bye bye");
      out->close = true;
      return;
  }
}

bool RtSession::RateTakes(double rate_hz) {
  switch (rate_) {
    case FrameRate::kAllFrames:
      return true;
    case FrameRate::kFrequencyDivisor:
      return divisor_count_++ % rate_value_ == 0;
    case FrameRate::kFrequency: {
      if (!(rate_hz > 0.0) || rate_value_ >= rate_hz) return true;
      // Frame k is sent when it brings the count sent up to floor(k * n / rate) + 1: about n
      // frames a second, spread evenly, the first one at once.
      const double due = std::floor(static_cast<double>(frequency_seen_++) * rate_value_ / rate_hz + 1e-9) + 1.0;
      if (static_cast<double>(frequency_sent_) >= due) return false;
      ++frequency_sent_;
      return true;
    }
  }
  return false;
}

void RtSession::OnFrame(const RtServerState& state, const RtEncoder& encode, RtOutput* out) {
  if (!streaming_ || !RateTakes(state.system.rate_hz)) return;
  PacketPtr packet = encode(stream_components_);
  if (udp_) out->udp.push_back(std::move(packet));
  else out->tcp.push_back({std::move(packet), true});
}

void RtSession::OnEvent(RtEvent event, RtOutput* out) {
  out->tcp.push_back({Share(MakeEventPacket(event)), false});
  if (event == RtEvent::kConnectionClosed && streaming_ && !udp_)
    out->tcp.push_back({Share(MakePacket(PacketType::kNoMoreData, "")), false});
}

}  // namespace mocap::stream::qtm

// Packet framing of the Qualisys RT protocol (see rt_packet.h).
#include "stream/qtm/rt_packet.h"

#include <algorithm>
#include <cstring>

namespace mocap::stream::qtm {

std::string MakePacket(PacketType type, const std::string& body) {
  std::string out;
  out.reserve(kHeaderSize + body.size());
  PutU32(&out, static_cast<uint32_t>(kHeaderSize + body.size()));
  PutU32(&out, static_cast<uint32_t>(type));
  out += body;
  return out;
}

std::string MakeStringPacket(PacketType type, const std::string& text) {
  std::string body = text;
  body.push_back('\0');
  return MakePacket(type, body);
}

std::string MakeEventPacket(RtEvent event) {
  return MakePacket(PacketType::kEvent, std::string(1, static_cast<char>(event)));
}

size_t PacketReader::Feed(const uint8_t* data, size_t size) {
  size_t used = 0;
  while (used < size && !broken_ && !ready_) {
    if (!in_body_) {
      const size_t take = std::min(kHeaderSize - header_fill_, size - used);
      std::memcpy(header_ + header_fill_, data + used, take);
      header_fill_ += take;
      used += take;
      if (header_fill_ < kHeaderSize) break;
      size_ = GetU32(header_);
      type_ = GetU32(header_ + 4);
      if (size_ < kHeaderSize || size_ > kMaxFramedPacket) {
        broken_ = true;
        broken_size_ = size_;
        break;
      }
      in_body_ = true;
      body_seen_ = 0;
      body_.clear();
    }
    const size_t body_size = size_ - kHeaderSize;
    const size_t take = std::min(body_size - body_seen_, size - used);
    if (body_size <= kMaxCommandPacket) body_.append(reinterpret_cast<const char*>(data + used), take);
    body_seen_ += take;
    used += take;
    if (body_seen_ == body_size) {
      pending_.type = type_;
      pending_.too_large = body_size > kMaxCommandPacket;
      pending_.body = std::move(body_);
      body_.clear();
      ready_ = true;
      in_body_ = false;
      header_fill_ = 0;
    }
  }
  return used;
}

bool PacketReader::Next(ReceivedPacket* packet) {
  if (!ready_) return false;
  *packet = std::move(pending_);
  pending_ = ReceivedPacket{};
  ready_ = false;
  return true;
}

}  // namespace mocap::stream::qtm

// Test helpers: split a byte stream the server sent into packets and read a data packet's
// components, written from the protocol's layout (independent of the encoder under test).
#pragma once

#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

namespace mocap::stream::qtm::testing {

struct Packet {
  uint32_t type = 0;
  std::string body;
  std::string Text() const { return body.empty() ? body : body.substr(0, body.size() - 1); }
};

inline uint32_t U32(const std::string& s, size_t at) {
  uint32_t v = 0;
  for (int i = 3; i >= 0; --i) v = v << 8 | static_cast<uint8_t>(s.at(at + i));
  return v;
}

inline float F32(const std::string& s, size_t at) {
  const uint32_t bits = U32(s, at);
  float v = 0;
  std::memcpy(&v, &bits, sizeof v);
  return v;
}

// Whole packets of `bytes`; a trailing partial packet stays in `bytes`.
inline std::vector<Packet> SplitPackets(std::string* bytes) {
  std::vector<Packet> out;
  size_t at = 0;
  while (bytes->size() - at >= 8) {
    const uint32_t size = U32(*bytes, at);
    if (size < 8 || bytes->size() - at < size) break;
    out.push_back({U32(*bytes, at + 4), bytes->substr(at + 8, size - 8)});
    at += size;
  }
  bytes->erase(0, at);
  return out;
}

struct Component {
  uint32_t type = 0;
  uint32_t count = 0;
  uint16_t drop = 0;
  std::string data;  // after count and rates
};

struct Frame {
  uint64_t timestamp = 0;
  uint32_t frame_number = 0;
  std::vector<Component> components;
};

inline Frame ReadFrame(const std::string& body) {
  Frame f;
  f.timestamp = U32(body, 0) | static_cast<uint64_t>(U32(body, 4)) << 32;
  f.frame_number = U32(body, 8);
  const uint32_t count = U32(body, 12);
  size_t at = 16;
  for (uint32_t i = 0; i < count; ++i) {
    Component c;
    const uint32_t size = U32(body, at);
    c.type = U32(body, at + 4);
    c.count = U32(body, at + 8);
    c.drop = static_cast<uint16_t>(static_cast<uint8_t>(body.at(at + 12)) | static_cast<uint8_t>(body.at(at + 13)) << 8);
    c.data = body.substr(at + 16, size - 16);
    f.components.push_back(c);
    at += size;
  }
  return f;
}

}  // namespace mocap::stream::qtm::testing

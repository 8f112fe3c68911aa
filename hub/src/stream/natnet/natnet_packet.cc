// NatNet packets at the byte level (see natnet_packet.h).
#include "stream/natnet/natnet_packet.h"

#include <cstring>

#include "util/little_endian.h"

namespace mocap::stream::natnet {
namespace {

// The connect payload: sSender (name, app version, NatNet version), then the connection
// options (u8 subscribed-data-only, u8[4] bitstream version) of 4.x clients.
constexpr size_t kSenderSize = kMaxNameLength + 8;
constexpr size_t kConnectVersionAt = kSenderSize + 1;
constexpr size_t kMaxCommand = 4096;  // longer command lines are not Motive's

Request Refuse(uint16_t id, std::string reason) {
  Request r;
  r.id = id;
  r.reason = std::move(reason);
  return r;
}

}  // namespace

bool Supported(const Version& v) { return (v.major == 3 || v.major == 4) && (v.minor == 0 || v.minor == 1); }

bool ParseVersion(const std::string& text, Version* out) {
  int major = -1, minor = -1, build = 0, revision = 0;
  char tail = 0;
  const int n = std::sscanf(text.c_str(), "%d.%d.%d.%d%c", &major, &minor, &build, &revision, &tail);
  if ((n != 2 && n != 4) || major < 0 || minor < 0 || major > 255 || minor > 255) return false;
  for (char c : text)
    if (!(c == '.' || (c >= '0' && c <= '9'))) return false;
  *out = Version{major, minor};
  return true;
}

std::string ToString(const Version& v) { return std::to_string(v.major) + "." + std::to_string(v.minor); }

Request ParseRequest(const uint8_t* data, size_t size) {
  if (size < kHeaderSize) return Refuse(0, "datagram of " + std::to_string(size) + " bytes is shorter than a header");
  if (size > kMaxPacket) return Refuse(0, "datagram of " + std::to_string(size) + " bytes exceeds " + std::to_string(kMaxPacket));
  const uint16_t id = le::GetU16(data);
  const size_t declared = le::GetU16(data + 2);
  if (declared > size - kHeaderSize)
    return Refuse(id, "header says " + std::to_string(declared) + " payload bytes, datagram has " +
                          std::to_string(size - kHeaderSize));
  const uint8_t* payload = data + kHeaderSize;
  Request r;
  r.id = id;
  switch (id) {
    case kConnect:
      if (declared >= kConnectVersionAt + 2 && payload[kConnectVersionAt] != 0) {
        r.asked = Version{payload[kConnectVersionAt], payload[kConnectVersionAt + 1]};
        r.asked_version = true;
      }
      break;
    case kRequest: {
      // The command line ends at its NUL or at the payload's end; it must be printable text.
      size_t length = 0;
      while (length < declared && payload[length] != 0) ++length;
      if (length == 0) return Refuse(id, "empty command");
      if (length > kMaxCommand) return Refuse(id, "command of " + std::to_string(length) + " bytes exceeds " + std::to_string(kMaxCommand));
      for (size_t i = 0; i < length; ++i)
        if (payload[i] < 0x20 || payload[i] > 0x7e) return Refuse(id, "command is not printable text");
      r.command.assign(reinterpret_cast<const char*>(payload), length);
      break;
    }
    default:
      break;
  }
  r.ok = true;
  return r;
}

Writer::Writer(uint16_t id) {
  U16(id);
  U16(0);
}

void Writer::I16(int16_t v) { U16(static_cast<uint16_t>(v)); }
void Writer::U16(uint16_t v) { le::PutU16(&bytes_, v); }
void Writer::I32(int32_t v) { U32(static_cast<uint32_t>(v)); }
void Writer::U32(uint32_t v) { le::PutU32(&bytes_, v); }
void Writer::U64(uint64_t v) { le::PutU64(&bytes_, v); }
void Writer::F32(float v) { le::PutF32(&bytes_, v); }
void Writer::F64(double v) { le::PutF64(&bytes_, v); }
void Writer::Str(const std::string& text) {
  bytes_.append(text.c_str());  // up to an embedded NUL, as a reader would see it
  U8(0);
}
void Writer::Fixed(const std::string& text, size_t size) {
  const std::string cut = text.substr(0, std::min(text.size(), size - 1));
  bytes_.append(cut);
  bytes_.append(size - cut.size(), '\0');
}
size_t Writer::Slot() {
  const size_t at = bytes_.size();
  U32(0);
  return at;
}
void Writer::PatchI32(size_t at, int32_t v) { le::PatchU32(&bytes_, at, static_cast<uint32_t>(v)); }
std::string Writer::Finish() {
  // Payloads beyond 65535 bytes cannot be told in the header: callers keep below kMaxPacket.
  const size_t payload = bytes_.size() - kHeaderSize;
  bytes_[2] = static_cast<char>(payload & 0xff);
  bytes_[3] = static_cast<char>((payload >> 8) & 0xff);
  return std::move(bytes_);
}

std::string EncodeServerInfo(const ServerInfo& info) {
  Writer w(kServerInfo);
  w.Fixed(info.application, kMaxNameLength);
  for (uint8_t v : info.app_version) w.U8(v);
  w.U8(static_cast<uint8_t>(info.version.major));
  w.U8(static_cast<uint8_t>(info.version.minor));
  w.U8(0);
  w.U8(0);
  w.U64(info.clock_frequency);
  w.U16(info.data_port);
  w.U8(info.multicast ? 1 : 0);
  for (uint8_t v : info.multicast_group) w.U8(v);
  return w.Finish();
}

std::string EncodeResponseInt(int32_t value) {
  Writer w(kResponse);
  w.I32(value);
  return w.Finish();
}

std::string EncodeResponseFloat(float value) {
  Writer w(kResponse);
  w.F32(value);
  return w.Finish();
}

std::string EncodeResponseString(const std::string& text) {
  Writer w(kResponse);
  w.Str(text);
  return w.Finish();
}

std::string EncodeMessageString(const std::string& text) {
  Writer w(kMessageString);
  w.Str(text);
  return w.Finish();
}

std::string EncodeUnrecognized() { return Writer(kUnrecognizedRequest).Finish(); }

}  // namespace mocap::stream::natnet

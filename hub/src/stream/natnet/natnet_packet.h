// Packets of OptiTrack's NatNet protocol (what Motive speaks on its command port 1510 and data
// port 1511) at the byte level: a 4-byte header (u16 message id, u16 payload bytes, little-endian)
// and a payload. This file reads what clients send (ParseRequest) and writes the small answers;
// natnet_frame.h writes model definitions and frames. Pure code: no I/O, no clock.
//
// Requests (client -> command port): NAT_CONNECT (payload optional: the client's sSender, then
// its connection options with the bitstream version it asks for), NAT_REQUEST (a command line,
// NUL-terminated), NAT_REQUEST_MODELDEF, NAT_REQUEST_FRAMEOFDATA, NAT_KEEPALIVE, NAT_DISCONNECT.
// A datagram shorter than its header says, longer than the protocol allows, or a command that is
// not text is refused with a reason (never read past its end).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

namespace mocap::stream::natnet {

enum MessageId : uint16_t {
  kConnect = 0,
  kServerInfo = 1,
  kRequest = 2,
  kResponse = 3,
  kRequestModelDef = 4,
  kModelDef = 5,
  kRequestFrameOfData = 6,
  kFrameOfData = 7,
  kMessageString = 8,
  kDisconnect = 9,
  kKeepAlive = 10,
  kUnrecognizedRequest = 100,
};

constexpr size_t kHeaderSize = 4;
// The largest datagram a NatNet client reads (its receive buffer); frames are kept below it.
constexpr size_t kMaxPacket = 65503;
constexpr size_t kMaxNameLength = 256;  // sSender's name field

// A bitstream version the server can write. The hub writes 3.0, 3.1, 4.0 and 4.1 (Motive 2.x
// to 3.1); 4.1 by default.
struct Version {
  int major = 4;
  int minor = 1;
  bool operator==(const Version& o) const { return major == o.major && minor == o.minor; }
  bool operator!=(const Version& o) const { return !(*this == o); }
};
bool Supported(const Version& v);
// "4.1" (and "4.1.0.0"); false for anything else.
bool ParseVersion(const std::string& text, Version* out);
std::string ToString(const Version& v);

struct Request {
  bool ok = false;
  std::string reason;        // why not ok
  uint16_t id = 0;
  std::string command;       // kRequest: the command line without its NUL
  Version asked;             // kConnect: the bitstream version in the client's options
  bool asked_version = false;  // the connect carried one (a 4.x client's)
};

Request ParseRequest(const uint8_t* data, size_t size);

// Little-endian writer of one packet: Begin() reserves the header, Finish() fills its size.
class Writer {
 public:
  explicit Writer(uint16_t id);
  void U8(uint8_t v) { bytes_.push_back(static_cast<char>(v)); }
  void I16(int16_t v);
  void U16(uint16_t v);
  void I32(int32_t v);
  void U32(uint32_t v);
  void U64(uint64_t v);
  void F32(float v);
  void F64(double v);
  void Str(const std::string& text);           // NUL-terminated
  void Fixed(const std::string& text, size_t size);  // NUL-padded to size (cut to size - 1)
  size_t size() const { return bytes_.size(); }
  // Reserves a 4-byte count/size slot and returns where it is, for PatchI32.
  size_t Slot();
  void PatchI32(size_t at, int32_t v);
  // The packet with its header's payload size filled in.
  std::string Finish();

 private:
  std::string bytes_;
};

struct ServerInfo {
  std::string application = "mocap-hub";
  uint8_t app_version[4] = {1, 0, 0, 0};
  Version version;
  uint64_t clock_frequency = 1'000'000'000;  // the stamps' ticks per second (ns)
  uint16_t data_port = 1511;
  bool multicast = true;
  uint8_t multicast_group[4] = {239, 255, 42, 99};
};
std::string EncodeServerInfo(const ServerInfo& info);
// NAT_RESPONSE carrying one value (an int32 result code or a float answer) or a string.
std::string EncodeResponseInt(int32_t value);
std::string EncodeResponseFloat(float value);
std::string EncodeResponseString(const std::string& text);
std::string EncodeMessageString(const std::string& text);
std::string EncodeUnrecognized();

}  // namespace mocap::stream::natnet

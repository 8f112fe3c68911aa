// The VRPN connection protocol (vrpn_Connection, version 07) at the byte level, and one client's
// side of it as a state machine without sockets.
//
// On a new TCP connection both sides send a 24-byte cookie ("vrpn: ver. 07.35", two spaces, the
// remote log mode digit, NUL padding) and check the other's: the text up to its last '.' must
// match (a minor version may differ), the log mode digit must be 0-3. After the cookies every
// message is a 24-byte header (big-endian u32 length = header + payload without padding, u32
// seconds, u32 microseconds, i32 sender, i32 type, u32 sequence number) and the payload padded
// to 8 bytes. Types below 0 are the connection's own: -1 sender description, -2 type
// description (both: u32 length of the name with its NUL, then the name), -3 UDP description,
// -4 log description, -5 disconnect. A side describes its senders and types before it uses
// their ids.
//
// The server side (VrpnSession): its senders are the trackers (one per rigid body, named after
// it, in the bodies file's order), its types "vrpn_Tracker Pos_Quat", "vrpn_Tracker Velocity"
// and "vrpn_Base pong_message". It keeps what the client describes (bounded tables), answers the
// client objects' "vrpn_Base ping_message" with a pong from the tracker of that name (so a
// vrpn_Tracker_Remote does not warn that the server is gone), ignores the client's UDP and log
// descriptions (everything goes over TCP, which clients read as they read UDP) and closes on a
// disconnect message, a bad cookie or a header that cannot be a message. Tracker reports:
// Pos_Quat = i32 sensor 0, 4 bytes padding, f64 position[3] (metres), f64 quaternion[4]
// (x, y, z, w; body -> world), big-endian; Velocity adds f64 velocity[3] (m/s), the rotation
// over vel_quat_dt as a quaternion and f64 vel_quat_dt (s). Pure code: no I/O, no clock.
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace mocap::stream::vrpn {

constexpr const char* kMagic = "vrpn: ver. 07.35";
constexpr size_t kCookieSize = 24;
constexpr size_t kHeaderSize = 24;
constexpr size_t kAlign = 8;
constexpr size_t kMaxNameLength = 95;  // vrpn_CNAME is 100 bytes with the u32 length before it
// A client's message beyond this is not one a VRPN client sends: the connection is closed.
constexpr size_t kMaxMessage = 64 * 1024;

enum SystemType : int32_t {
  kSenderDescription = -1,
  kTypeDescription = -2,
  kUdpDescription = -3,
  kLogDescription = -4,
  kDisconnectMessage = -5,
};

// The server's own type ids.
enum TypeId : int32_t { kPosQuat = 0, kVelocity = 1, kPong = 2 };
extern const char* const kTypeNames[3];

std::string Cookie();
// Empty when `cookie` (kCookieSize bytes) is one this side can talk to; else why not.
std::string CheckCookie(const uint8_t* cookie);

struct Timestamp {
  uint32_t seconds = 0;
  uint32_t microseconds = 0;
};
Timestamp FromNs(uint64_t ns);

// One whole message, padded.
std::string Message(int32_t type, int32_t sender, Timestamp time, const std::string& payload, uint32_t sequence = 0);
std::string Description(SystemType which, int32_t id, const std::string& name);
std::string PosQuatPayload(const Eigen::Vector3d& position_m, const Eigen::Quaterniond& orientation);
std::string VelocityPayload(const Eigen::Vector3d& velocity_m_s, const Eigen::Quaterniond& rotation, double dt_s);

struct ReceivedMessage {
  int32_t type = 0;
  int32_t sender = 0;
  Timestamp time;
  std::string payload;  // without padding
};

// Cuts a TCP byte stream (after the cookie) into messages with bounded memory.
class MessageReader {
 public:
  // Takes bytes; returns how many it used. Stop once broken().
  size_t Feed(const uint8_t* data, size_t size);
  bool Next(ReceivedMessage* message);
  bool broken() const { return !reason_.empty(); }
  const std::string& reason() const { return reason_; }

 private:
  std::string buffer_;
  size_t need_ = kHeaderSize;  // bytes the current message takes (header, then padded whole)
  bool have_header_ = false;
  uint32_t length_ = 0;
  std::vector<ReceivedMessage> ready_;
  std::string reason_;
};

class VrpnSession {
 public:
  // Bounds on what a client may describe.
  static constexpr size_t kMaxRemoteNames = 1024;

  explicit VrpnSession(std::vector<std::string> trackers);

  // Bytes from the client; what to send back is appended to *out. Stop once closed().
  void Receive(const uint8_t* data, size_t size, uint64_t now_ns, std::string* out);
  // Cookies exchanged and the server's descriptions sent: reports may go to this client.
  bool connected() const { return state_ == State::kConnected; }
  bool closed() const { return state_ == State::kClosed; }
  const std::string& close_reason() const { return close_reason_; }
  uint64_t pongs() const { return pongs_; }

 private:
  enum class State { kCookie, kConnected, kClosed };
  void Handle(const ReceivedMessage& m, uint64_t now_ns, std::string* out);
  void Close(std::string reason);

  std::vector<std::string> trackers_;
  State state_ = State::kCookie;
  std::string cookie_;
  MessageReader reader_;
  std::map<int32_t, std::string> remote_types_;
  std::map<int32_t, std::string> remote_senders_;
  std::string close_reason_;
  uint64_t pongs_ = 0;
};

}  // namespace mocap::stream::vrpn

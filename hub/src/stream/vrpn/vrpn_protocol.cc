// The VRPN connection protocol and one client's session (see vrpn_protocol.h).
#include "stream/vrpn/vrpn_protocol.h"

#include <arpa/inet.h>

#include <cstring>

namespace mocap::stream::vrpn {
namespace {

constexpr const char* kPing = "vrpn_Base ping_message";
constexpr size_t kMagicLength = 16;
constexpr size_t kLogModeAt = kMagicLength + 2;

size_t Padded(size_t n) { return (n + kAlign - 1) / kAlign * kAlign; }

void PutU32(std::string* out, uint32_t v) {
  const uint32_t be = htonl(v);
  out->append(reinterpret_cast<const char*>(&be), 4);
}

void PutF64(std::string* out, double v) {
  uint64_t bits;
  std::memcpy(&bits, &v, 8);
  for (int i = 7; i >= 0; --i) out->push_back(static_cast<char>(bits >> (8 * i)));
}

uint32_t GetU32(const char* p) {
  uint32_t be;
  std::memcpy(&be, p, 4);
  return ntohl(be);
}

}  // namespace

const char* const kTypeNames[3] = {"vrpn_Tracker Pos_Quat", "vrpn_Tracker Velocity", "vrpn_Base pong_message"};

std::string Cookie() {
  std::string c = std::string(kMagic) + "  0";
  c.resize(kCookieSize, '\0');
  return c;
}

std::string CheckCookie(const uint8_t* cookie) {
  const std::string text(reinterpret_cast<const char*>(cookie), kCookieSize);
  const std::string printable = text.substr(0, text.find('\0'));
  // The major version is everything up to the last '.' of the magic text.
  const size_t dot = text.substr(0, kMagicLength).rfind('.');
  if (dot == std::string::npos || text.compare(0, dot + 1, kMagic, dot + 1) != 0)
    return "bad cookie '" + printable + "' (this server speaks '" + kMagic + "')";
  const char mode = text[kLogModeAt];
  if (mode < '0' || mode > '3') return "bad log mode in cookie '" + printable + "'";
  return "";
}

Timestamp FromNs(uint64_t ns) {
  return Timestamp{static_cast<uint32_t>(ns / 1'000'000'000ull), static_cast<uint32_t>(ns % 1'000'000'000ull / 1000)};
}

std::string Message(int32_t type, int32_t sender, Timestamp time, const std::string& payload, uint32_t sequence) {
  std::string m;
  m.reserve(kHeaderSize + Padded(payload.size()));
  PutU32(&m, static_cast<uint32_t>(kHeaderSize + payload.size()));
  PutU32(&m, time.seconds);
  PutU32(&m, time.microseconds);
  PutU32(&m, static_cast<uint32_t>(sender));
  PutU32(&m, static_cast<uint32_t>(type));
  PutU32(&m, sequence);
  m += payload;
  m.resize(kHeaderSize + Padded(payload.size()), '\0');
  return m;
}

std::string Description(SystemType which, int32_t id, const std::string& name) {
  std::string payload;
  const std::string cut = name.substr(0, kMaxNameLength);
  PutU32(&payload, static_cast<uint32_t>(cut.size() + 1));
  payload += cut;
  payload.push_back('\0');
  return Message(which, id, Timestamp{}, payload);
}

std::string PosQuatPayload(const Eigen::Vector3d& position_m, const Eigen::Quaterniond& orientation) {
  std::string p;
  PutU32(&p, 0);  // sensor
  PutU32(&p, 0);  // alignment
  for (int i = 0; i < 3; ++i) PutF64(&p, position_m[i]);
  const Eigen::Quaterniond q = orientation.normalized();
  for (double v : {q.x(), q.y(), q.z(), q.w()}) PutF64(&p, v);
  return p;
}

std::string VelocityPayload(const Eigen::Vector3d& velocity_m_s, const Eigen::Quaterniond& rotation, double dt_s) {
  std::string p;
  PutU32(&p, 0);
  PutU32(&p, 0);
  for (int i = 0; i < 3; ++i) PutF64(&p, velocity_m_s[i]);
  const Eigen::Quaterniond q = rotation.normalized();
  for (double v : {q.x(), q.y(), q.z(), q.w()}) PutF64(&p, v);
  PutF64(&p, dt_s);
  return p;
}

size_t MessageReader::Feed(const uint8_t* data, size_t size) {
  size_t used = 0;
  while (used < size && !broken()) {
    const size_t take = std::min(need_ - buffer_.size(), size - used);
    buffer_.append(reinterpret_cast<const char*>(data + used), take);
    used += take;
    if (buffer_.size() < need_) break;
    if (!have_header_) {
      length_ = GetU32(buffer_.data());
      if (length_ < kHeaderSize || length_ > kMaxMessage) {
        reason_ = "message length " + std::to_string(length_) + " outside " + std::to_string(kHeaderSize) + "-" +
                  std::to_string(kMaxMessage);
        break;
      }
      have_header_ = true;
      need_ = kHeaderSize + Padded(length_ - kHeaderSize);
      if (buffer_.size() < need_) continue;
    }
    ReceivedMessage m;
    m.time = Timestamp{GetU32(buffer_.data() + 4), GetU32(buffer_.data() + 8)};
    m.sender = static_cast<int32_t>(GetU32(buffer_.data() + 12));
    m.type = static_cast<int32_t>(GetU32(buffer_.data() + 16));
    m.payload = buffer_.substr(kHeaderSize, length_ - kHeaderSize);
    ready_.push_back(std::move(m));
    buffer_.clear();
    have_header_ = false;
    need_ = kHeaderSize;
  }
  return used;
}

bool MessageReader::Next(ReceivedMessage* message) {
  if (ready_.empty()) return false;
  *message = std::move(ready_.front());
  ready_.erase(ready_.begin());
  return true;
}

VrpnSession::VrpnSession(std::vector<std::string> trackers) : trackers_(std::move(trackers)) {}

void VrpnSession::Close(std::string reason) {
  state_ = State::kClosed;
  close_reason_ = std::move(reason);
}

void VrpnSession::Receive(const uint8_t* data, size_t size, uint64_t now_ns, std::string* out) {
  size_t at = 0;
  if (state_ == State::kCookie) {
    const size_t take = std::min(kCookieSize - cookie_.size(), size);
    cookie_.append(reinterpret_cast<const char*>(data), take);
    at = take;
    if (cookie_.size() < kCookieSize) return;
    const std::string bad = CheckCookie(reinterpret_cast<const uint8_t*>(cookie_.data()));
    if (!bad.empty()) return Close(bad);
    state_ = State::kConnected;
    for (size_t i = 0; i < trackers_.size(); ++i)
      *out += Description(kSenderDescription, static_cast<int32_t>(i), trackers_[i]);
    for (int32_t t = 0; t < 3; ++t) *out += Description(kTypeDescription, t, kTypeNames[t]);
  }
  while (at < size && state_ == State::kConnected) {
    at += reader_.Feed(data + at, size - at);
    ReceivedMessage m;
    while (state_ == State::kConnected && reader_.Next(&m)) Handle(m, now_ns, out);
    if (reader_.broken()) Close(reader_.reason());
  }
}

void VrpnSession::Handle(const ReceivedMessage& m, uint64_t now_ns, std::string* out) {
  if (m.type == kSenderDescription || m.type == kTypeDescription) {
    if (m.payload.size() < 4) return Close("description of " + std::to_string(m.payload.size()) + " bytes");
    const uint32_t length = GetU32(m.payload.data());
    if (length == 0 || length > m.payload.size() - 4 || length > kMaxNameLength + 1)
      return Close("description's name length " + std::to_string(length) + " does not fit its message");
    std::string name = m.payload.substr(4, length);
    name = name.substr(0, name.find('\0'));
    auto& table = m.type == kSenderDescription ? remote_senders_ : remote_types_;
    if (table.size() >= kMaxRemoteNames && !table.count(m.sender))
      return Close("more than " + std::to_string(kMaxRemoteNames) + " names described");
    table[m.sender] = name;
    return;
  }
  if (m.type == kDisconnectMessage) return Close("client disconnected");
  if (m.type < 0) return;  // UDP and log descriptions: everything goes over TCP, nothing is logged
  const auto type = remote_types_.find(m.type);
  if (type == remote_types_.end() || type->second != kPing) return;
  const auto sender = remote_senders_.find(m.sender);
  if (sender == remote_senders_.end()) return;
  for (size_t i = 0; i < trackers_.size(); ++i)
    if (trackers_[i] == sender->second) {
      *out += Message(kPong, static_cast<int32_t>(i), FromNs(now_ns), "");
      ++pongs_;
      return;
    }
}

}  // namespace mocap::stream::vrpn

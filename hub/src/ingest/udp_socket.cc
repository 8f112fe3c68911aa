// UDP socket wrapper (see udp_socket.h). Kernel receive timestamps (SO_TIMESTAMPNS) make the
// latency figures independent of how quickly the hub's loop gets to the datagram.
#include "ingest/udp_socket.h"

#include <arpa/inet.h>
#include <netdb.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cstring>
#include <ctime>
#include <stdexcept>

namespace mocap {

HostPort ParseHostPort(const std::string& text) {
  const size_t colon = text.rfind(':');
  if (colon == std::string::npos) throw std::invalid_argument("address '" + text + "' is not HOST:PORT");
  HostPort hp;
  hp.host = text.substr(0, colon);
  if (hp.host == "*") hp.host.clear();
  const std::string port = text.substr(colon + 1);
  char* end = nullptr;
  errno = 0;
  const long value = std::strtol(port.c_str(), &end, 10);
  // The whole port, not up to a NUL (a config file line may hold one: "30000\0junk" was 30000).
  if (port.empty() || end != port.c_str() + port.size() || errno != 0 || value < 0 || value > 65535)
    throw std::invalid_argument("address '" + text + "': port must be 0-65535");
  hp.port = static_cast<uint16_t>(value);
  return hp;
}

sockaddr_in ResolveHostPort(const HostPort& hp) {
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_port = htons(hp.port);
  if (hp.host.empty()) {
    addr.sin_addr.s_addr = htonl(INADDR_ANY);
    return addr;
  }
  if (inet_pton(AF_INET, hp.host.c_str(), &addr.sin_addr) == 1) return addr;
  addrinfo hints{};
  hints.ai_family = AF_INET;
  hints.ai_socktype = SOCK_DGRAM;
  addrinfo* result = nullptr;
  const int rc = getaddrinfo(hp.host.c_str(), nullptr, &hints, &result);
  if (rc != 0 || !result) throw std::runtime_error("cannot resolve '" + hp.host + "': " + gai_strerror(rc));
  addr.sin_addr = reinterpret_cast<sockaddr_in*>(result->ai_addr)->sin_addr;
  freeaddrinfo(result);
  return addr;
}

uint64_t RealtimeNowNs() {
  timespec ts{};
  clock_gettime(CLOCK_REALTIME, &ts);
  return uint64_t(ts.tv_sec) * 1'000'000'000ull + uint64_t(ts.tv_nsec);
}

std::string SockaddrToString(const sockaddr_in& address) {
  char buf[INET_ADDRSTRLEN] = "?";
  inet_ntop(AF_INET, &address.sin_addr, buf, sizeof buf);
  return std::string(buf) + ":" + std::to_string(ntohs(address.sin_port));
}

std::string Datagram::FromString() const { return SockaddrToString(from); }

const std::string& SourceText::Of(const sockaddr_in& address) {
  if (text_.empty() || address.sin_addr.s_addr != last_.sin_addr.s_addr || address.sin_port != last_.sin_port) {
    last_ = address;
    text_ = SockaddrToString(address);
  }
  return text_;
}

namespace {

// The kernel's receive time of a datagram (SO_TIMESTAMPNS), else now.
uint64_t ReceiveTimeOf(const msghdr& msg) {
  for (cmsghdr* c = CMSG_FIRSTHDR(&msg); c; c = CMSG_NXTHDR(const_cast<msghdr*>(&msg), c)) {
    if (c->cmsg_level == SOL_SOCKET && c->cmsg_type == SCM_TIMESTAMPNS) {
      timespec ts{};
      std::memcpy(&ts, CMSG_DATA(c), sizeof ts);
      return uint64_t(ts.tv_sec) * 1'000'000'000ull + uint64_t(ts.tv_nsec);
    }
  }
  return RealtimeNowNs();
}

}  // namespace

UdpSocket::~UdpSocket() {
  if (fd_ >= 0) close(fd_);
}

void UdpSocket::Bind(const HostPort& address) {
  const std::string where = (address.host.empty() ? "*" : address.host) + ":" + std::to_string(address.port);
  fd_ = socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
  if (fd_ < 0) throw std::runtime_error("socket: " + std::string(std::strerror(errno)));
  const int one = 1;
  setsockopt(fd_, SOL_SOCKET, SO_TIMESTAMPNS, &one, sizeof one);
  // A deep receive buffer absorbs bursts from many nodes (and a flood's) while the hub is busy
  // with a frame: beyond net.core.rmem_max where the process may (CAP_NET_ADMIN), else up to it.
  const int rcvbuf = kReceiveBuffer;
  if (setsockopt(fd_, SOL_SOCKET, SO_RCVBUFFORCE, &rcvbuf, sizeof rcvbuf) != 0)
    setsockopt(fd_, SOL_SOCKET, SO_RCVBUF, &rcvbuf, sizeof rcvbuf);
  const sockaddr_in addr = ResolveHostPort(address);
  if (bind(fd_, reinterpret_cast<const sockaddr*>(&addr), sizeof addr) != 0)
    throw std::runtime_error("cannot listen on " + where + ": " + std::strerror(errno));
}

void UdpSocket::EnableBroadcast() {
  const int one = 1;
  if (setsockopt(fd_, SOL_SOCKET, SO_BROADCAST, &one, sizeof one) != 0)
    throw std::runtime_error("cannot enable broadcast: " + std::string(std::strerror(errno)));
}

void UdpSocket::EnableMulticast(int ttl) {
  const unsigned char hops = static_cast<unsigned char>(ttl), loop = 1;
  if (setsockopt(fd_, IPPROTO_IP, IP_MULTICAST_TTL, &hops, sizeof hops) != 0 ||
      setsockopt(fd_, IPPROTO_IP, IP_MULTICAST_LOOP, &loop, sizeof loop) != 0)
    throw std::runtime_error("cannot enable multicast: " + std::string(std::strerror(errno)));
}

uint16_t UdpSocket::port() const {
  sockaddr_in addr{};
  socklen_t len = sizeof addr;
  if (getsockname(fd_, reinterpret_cast<sockaddr*>(&addr), &len) != 0) return 0;
  return ntohs(addr.sin_port);
}

size_t UdpSocket::Drain(int first_wait_ms, size_t max_datagrams,
                        const std::function<void(const Datagram&)>& handle) {
  if (max_datagrams == 0 || !WaitReadable(first_wait_ms)) return 0;
  // recvmmsg: up to kBatch datagrams a system call, into slots allocated once; a short batch
  // means the queue is empty.
  if (batch_buffer_.empty()) {
    batch_buffer_.resize(kBatch * kMaxDatagram);
    batch_.resize(kBatch);
  }
  std::array<mmsghdr, kBatch> msgs{};
  std::array<iovec, kBatch> iov{};
  alignas(cmsghdr) char control[kBatch][kControlSize];
  size_t n = 0;
  while (n < max_datagrams) {
    const unsigned want = static_cast<unsigned>(std::min(kBatch, max_datagrams - n));
    for (unsigned i = 0; i < want; ++i) {
      iov[i] = {batch_buffer_.data() + i * kMaxDatagram, kMaxDatagram};
      msghdr& m = msgs[i].msg_hdr;
      m = msghdr{};
      m.msg_name = &batch_[i].from;
      m.msg_namelen = sizeof batch_[i].from;
      m.msg_iov = &iov[i];
      m.msg_iovlen = 1;
      m.msg_control = control[i];
      m.msg_controllen = kControlSize;
    }
    const int got = recvmmsg(fd_, msgs.data(), want, MSG_DONTWAIT, nullptr);
    if (got < 0) {
      if (errno == EAGAIN || errno == EINTR) break;
      throw std::runtime_error("recvmmsg: " + std::string(std::strerror(errno)));
    }
    for (size_t i = 0; i < static_cast<size_t>(got); ++i) {
      Datagram& d = batch_[i];
      const uint8_t* bytes = batch_buffer_.data() + i * kMaxDatagram;
      d.bytes.assign(bytes, bytes + msgs[i].msg_len);
      d.receive_time_ns = ReceiveTimeOf(msgs[i].msg_hdr);
      handle(d);
    }
    n += static_cast<size_t>(got);
    if (static_cast<unsigned>(got) < want) break;
  }
  return n;
}

bool UdpSocket::WaitReadable(int timeout_ms) const {
  pollfd pfd{fd_, POLLIN, 0};
  const int ready = poll(&pfd, 1, timeout_ms);
  if (ready < 0 && errno != EINTR) throw std::runtime_error("poll: " + std::string(std::strerror(errno)));
  return ready > 0;
}

bool UdpSocket::Receive(Datagram* d, int timeout_ms) {
  if (!WaitReadable(timeout_ms)) return false;
  // The datagram lands in the socket's own buffer (allocated once, never zero-filled again) and
  // is copied out at its length. IPv4 cannot carry more than kMaxDatagram, so nothing is cut.
  if (buffer_.empty()) buffer_.resize(kMaxDatagram);
  iovec iov{buffer_.data(), buffer_.size()};
  alignas(cmsghdr) char control[kControlSize];
  msghdr msg{};
  msg.msg_name = &d->from;
  msg.msg_namelen = sizeof d->from;
  msg.msg_iov = &iov;
  msg.msg_iovlen = 1;
  msg.msg_control = control;
  msg.msg_controllen = sizeof control;
  const ssize_t n = recvmsg(fd_, &msg, MSG_DONTWAIT);
  if (n < 0) {
    if (errno == EAGAIN || errno == EINTR) return false;
    throw std::runtime_error("recvmsg: " + std::string(std::strerror(errno)));
  }
  d->bytes.assign(buffer_.begin(), buffer_.begin() + n);
  d->receive_time_ns = ReceiveTimeOf(msg);
  return true;
}

bool UdpSocket::SendTo(const HostPort& to, const std::vector<uint8_t>& bytes) {
  return SendTo(ResolveHostPort(to), bytes.data(), bytes.size());
}

bool UdpSocket::SendTo(const sockaddr_in& to, const uint8_t* bytes, size_t size) {
  return sendto(fd_, bytes, size, MSG_DONTWAIT, reinterpret_cast<const sockaddr*>(&to), sizeof to) ==
         static_cast<ssize_t>(size);
}

}  // namespace mocap

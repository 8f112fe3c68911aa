// A UDP socket for the hub: bind, receive with a timeout and kernel receive time, send.
// Errors from the OS throw std::runtime_error naming the address and the reason.
#pragma once

#include <netinet/in.h>

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace mocap {

struct HostPort {
  std::string host;
  uint16_t port = 0;
};
// "HOST:PORT" (HOST may be empty or "*" for any address). Throws std::invalid_argument.
HostPort ParseHostPort(const std::string& text);
// The IPv4 address of HOST:PORT (names resolved once). Throws std::runtime_error.
sockaddr_in ResolveHostPort(const HostPort& address);
std::string SockaddrToString(const sockaddr_in& address);

struct Datagram {
  std::vector<uint8_t> bytes;
  uint64_t receive_time_ns = 0;  // CLOCK_REALTIME, from the kernel when available
  sockaddr_in from{};
  std::string FromString() const;
};

// A source address as "HOST:PORT", written out only when it differs from the last one asked
// (a flood comes from few addresses: a loop names each datagram's sender without formatting it).
class SourceText {
 public:
  const std::string& Of(const sockaddr_in& address);

 private:
  sockaddr_in last_{};
  std::string text_;
};

class UdpSocket {
 public:
  UdpSocket() = default;
  ~UdpSocket();
  UdpSocket(const UdpSocket&) = delete;
  UdpSocket& operator=(const UdpSocket&) = delete;

  void Bind(const HostPort& address);
  void EnableBroadcast();
  // Datagrams to multicast groups leave with this TTL (1: the local network only) and loop
  // back to listeners on this host.
  void EnableMulticast(int ttl);
  uint16_t port() const;
  // The largest UDP payload IPv4 carries; Receive's buffer holds it whole.
  static constexpr size_t kMaxDatagram = 65507;
  // Waits up to timeout_ms for one datagram; false on timeout or EINTR.
  bool Receive(Datagram* datagram, int timeout_ms);
  // The receive step of the hub's loops (serve's and record's): waits up to
  // first_wait_ms for a first datagram, then takes what is queued without waiting, kBatch a
  // system call (recvmmsg), at most max_datagrams, so that a flood still leaves the loop its
  // other work; each goes to `handle` (valid during the call). Returns how many came.
  size_t Drain(int first_wait_ms, size_t max_datagrams, const std::function<void(const Datagram&)>& handle);
  static constexpr size_t kDrainMax = 4096;  // the hub loop's bound
  static constexpr size_t kBatch = 32;
  // The receive buffer Bind asks for (granted up to net.core.rmem_max without CAP_NET_ADMIN).
  static constexpr int kReceiveBuffer = 64 * 1024 * 1024;
  // Best effort: a full send buffer or an unreachable peer is reported by the return value.
  bool SendTo(const HostPort& to, const std::vector<uint8_t>& bytes);
  bool SendTo(const sockaddr_in& to, const uint8_t* bytes, size_t size);
  int fd() const { return fd_; }

 private:
  bool WaitReadable(int timeout_ms) const;  // false on timeout or EINTR
  static constexpr size_t kControlSize = 256;

  int fd_ = -1;
  std::vector<uint8_t> buffer_;        // Receive's
  std::vector<uint8_t> batch_buffer_;  // Drain's: kBatch slots of kMaxDatagram
  std::vector<Datagram> batch_;
};

uint64_t RealtimeNowNs();

}  // namespace mocap

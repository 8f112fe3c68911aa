// The VRPN server's sockets and thread (see vrpn_server.h).
#include "stream/vrpn/vrpn_server.h"
#include "stream/publish_latency.h"

#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "ingest/udp_socket.h"
#include "util/log.h"

namespace mocap::stream::vrpn {
namespace {

constexpr int kIdlePollMs = 100;
constexpr size_t kReadChunk = 16 * 1024;
constexpr size_t kMaxReadPerTurn = 64 * 1024;
constexpr size_t kMaxLookup = 150;  // "IP PORT" with its NUL, as VRPN clients write it
constexpr double kMetresPerMm = 1e-3;

std::runtime_error SocketError(const std::string& what) {
  return std::runtime_error("vrpn: " + what + ": " + std::strerror(errno));
}

}  // namespace

struct VrpnServer::Client {
  int fd = -1;
  sockaddr_in peer{};
  bool connecting = false;  // a lookup's outgoing connect not yet complete
  std::unique_ptr<VrpnSession> session;
  bool counted = false;     // connected() seen
  std::deque<std::shared_ptr<const std::string>> queue;
  size_t queued_bytes = 0;
  size_t front_sent = 0;
  bool dead = false;
};

void VrpnOptions::Check() const {
  ParseHostPort(listen);
  if (max_clients == 0) throw std::invalid_argument("vrpn: max clients must be > 0");
  if (client_frame_bytes == 0 || client_reply_bytes < client_frame_bytes)
    throw std::invalid_argument("vrpn: client queue bounds must be > 0, answers' at least the frames'");
  if (queue_frames == 0) throw std::invalid_argument("vrpn: queue must hold at least one frame");
}

VrpnServer::VrpnServer(VrpnOptions options, std::vector<std::string> trackers)
    : options_((options.Check(), std::move(options))), trackers_(std::move(trackers)), last_(trackers_.size()),
      queue_(options_.queue_frames, "vrpn") {
  const HostPort where = ParseHostPort(options_.listen);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_port = htons(where.port);
  if (where.host.empty() || where.host == "*") addr.sin_addr.s_addr = htonl(INADDR_ANY);
  else addr = ResolveHostPort(where);
  listen_fd_ = socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC | SOCK_NONBLOCK, 0);
  udp_fd_ = socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC | SOCK_NONBLOCK, 0);
  const int one = 1;
  if (listen_fd_ >= 0) setsockopt(listen_fd_, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
  bool ok = listen_fd_ >= 0 && udp_fd_ >= 0 &&
            bind(listen_fd_, reinterpret_cast<const sockaddr*>(&addr), sizeof addr) == 0 &&
            listen(listen_fd_, SOMAXCONN) == 0;
  if (ok) {
    socklen_t len = sizeof addr;
    getsockname(listen_fd_, reinterpret_cast<sockaddr*>(&addr), &len);
    port_ = ntohs(addr.sin_port);
    ok = bind(udp_fd_, reinterpret_cast<const sockaddr*>(&addr), sizeof addr) == 0;
  }
  if (!ok) {
    const std::runtime_error error = SocketError("cannot listen on " + options_.listen);
    for (int fd : {listen_fd_, udp_fd_})
      if (fd >= 0) close(fd);
    throw error;
  }
  thread_ = std::thread([this] { Run(); });
}

VrpnServer::~VrpnServer() {
  stop_ = true;
  queue_.Wake();
  if (thread_.joinable()) thread_.join();
  for (auto& c : clients_) close(c->fd);
  close(listen_fd_);
  close(udp_fd_);
}

void VrpnServer::Publish(SharedFrame frame) {
  // Never waits: while the thread holds the clients the frame queues for it.
  std::unique_lock<std::mutex> lock(clients_mutex_, std::try_to_lock);
  if (lock.owns_lock() && clients_.size() <= options_.inline_clients) {
    SendQueued();
    SendFrame(*frame, true);
    // Bytes a client's socket did not take wait for the thread's poll to see it writable.
    for (const auto& c : clients_)
      if (!c->queue.empty()) return queue_.Wake();
    return;
  }
  if (lock.owns_lock()) lock.unlock();
  queue_.Push(std::move(frame));
}

void VrpnServer::SendQueued() {
  while (SharedFrame frame = queue_.PopNow()) SendFrame(*frame, false);
}

VrpnStats VrpnServer::stats() const {
  std::lock_guard<std::mutex> lock(stats_mutex_);
  VrpnStats s = stats_;
  s.frames_dropped += queue_.dropped();
  return s;
}

nlohmann::json VrpnServer::StatsJson() const {
  const VrpnStats s = stats();
  std::lock_guard<std::mutex> lock(stats_mutex_);
  nlohmann::json out = {{"port", port_},
          {"trackers", trackers_},
          {"clients", s.clients},
          {"connections", s.connections},
          {"lookups", s.lookups},
          {"refused", s.refused},
          {"frames", s.frames},
          {"frames_on_publish", s.frames_on_publish},
          {"reports", s.reports},
          {"frames_dropped", s.frames_dropped}};
  out.update(latency_.Json("VRPN report"));
  return out;
}

void VrpnServer::Run() {
  std::vector<pollfd> fds;
  while (!stop_) {
    {
      std::lock_guard<std::mutex> lock(clients_mutex_);
      fds.clear();
      fds.push_back({listen_fd_, POLLIN, 0});
      fds.push_back({udp_fd_, POLLIN, 0});
      fds.push_back({queue_.fd(), POLLIN, 0});
      for (const auto& c : clients_)
        fds.push_back({c->fd, static_cast<short>(c->connecting ? POLLOUT : (POLLIN | (c->queue.empty() ? 0 : POLLOUT))), 0});
    }
    // Publish() may send meanwhile (it only marks clients dead: the list and its order hold).
    if (poll(fds.data(), fds.size(), kIdlePollMs) < 0 && errno != EINTR) {
      log::Error("vrpn: poll failed: {}", std::strerror(errno));
      break;
    }
    std::lock_guard<std::mutex> lock(clients_mutex_);
    if (fds[2].revents & POLLIN) queue_.Acknowledge();
    SendQueued();
    const size_t polled = fds.size() - 3;
    for (size_t i = 0; i < polled && i < clients_.size(); ++i) {
      Client& c = *clients_[i];
      const short revents = fds[i + 3].revents;
      if (c.connecting) {
        if (!(revents & (POLLOUT | POLLERR | POLLHUP))) continue;
        int error = 0;
        socklen_t len = sizeof error;
        getsockopt(c.fd, SOL_SOCKET, SO_ERROR, &error, &len);
        if (error) {
          log::Debug("vrpn: cannot connect back to {}: {}", SockaddrToString(c.peer), std::strerror(error));
          c.dead = true;
          continue;
        }
        c.connecting = false;
        Queue(c, std::make_shared<const std::string>(Cookie()), false);
        continue;
      }
      if (revents & POLLNVAL) c.dead = true;
      if (!c.dead && (revents & (POLLIN | POLLHUP | POLLERR))) Read(c);
      if (!c.dead && (revents & POLLOUT)) Flush(c);
    }
    if (fds[0].revents & POLLIN) Accept();
    if (fds[1].revents & POLLIN) Lookups();
    CloseDead();
  }
}

void VrpnServer::Accept() {
  for (int i = 0; i < 256; ++i) {
    sockaddr_in peer{};
    socklen_t len = sizeof peer;
    const int fd = accept4(listen_fd_, reinterpret_cast<sockaddr*>(&peer), &len, SOCK_NONBLOCK | SOCK_CLOEXEC);
    if (fd < 0) return;
    if (clients_.size() >= options_.max_clients) {
      close(fd);
      std::lock_guard<std::mutex> lock(stats_mutex_);
      ++stats_.refused;
      continue;
    }
    const int one = 1;
    setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
    auto c = std::make_unique<Client>();
    c->fd = fd;
    c->peer = peer;
    c->session = std::make_unique<VrpnSession>(trackers_);
    Queue(*c, std::make_shared<const std::string>(Cookie()), false);
    clients_.push_back(std::move(c));
  }
}

void VrpnServer::Lookups() {
  uint64_t lookups = 0, refused = 0;
  for (int i = 0; i < 256; ++i) {
    char buffer[kMaxLookup + 1];
    sockaddr_in from{};
    socklen_t len = sizeof from;
    const ssize_t n = recvfrom(udp_fd_, buffer, kMaxLookup, 0, reinterpret_cast<sockaddr*>(&from), &len);
    if (n < 0) break;
    buffer[n] = '\0';
    char host[100] = {};
    int port = 0;
    char tail = 0;
    in_addr named{};
    const bool parsed = std::sscanf(buffer, "%99s %d%c", host, &port, &tail) == 2 && port > 0 && port < 65536 &&
                        inet_pton(AF_INET, host, &named) == 1;
    if (!parsed || named.s_addr != from.sin_addr.s_addr || clients_.size() >= options_.max_clients) {
      log::Debug("vrpn: lookup from {} refused", SockaddrToString(from));
      ++refused;
      continue;
    }
    sockaddr_in to = from;
    to.sin_port = htons(static_cast<uint16_t>(port));
    bool known = false;
    for (const auto& c : clients_)
      known |= c->peer.sin_addr.s_addr == to.sin_addr.s_addr && c->peer.sin_port == to.sin_port;
    if (known) continue;  // VRPN clients repeat their request until called back
    const int fd = socket(AF_INET, SOCK_STREAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
    if (fd < 0) break;
    if (connect(fd, reinterpret_cast<const sockaddr*>(&to), sizeof to) != 0 && errno != EINPROGRESS) {
      close(fd);
      ++refused;
      continue;
    }
    const int one = 1;
    setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
    auto c = std::make_unique<Client>();
    c->fd = fd;
    c->peer = to;
    c->connecting = true;
    c->session = std::make_unique<VrpnSession>(trackers_);
    clients_.push_back(std::move(c));
    ++lookups;
  }
  std::lock_guard<std::mutex> lock(stats_mutex_);
  stats_.lookups += lookups;
  stats_.refused += refused;
}

void VrpnServer::Read(Client& c) {
  uint8_t buffer[kReadChunk];
  size_t total = 0;
  while (total < kMaxReadPerTurn && !c.dead) {
    const ssize_t n = recv(c.fd, buffer, sizeof buffer, 0);
    if (n == 0) {
      c.dead = true;
      return;
    }
    if (n < 0) {
      if (errno == EINTR) continue;
      if (errno != EAGAIN && errno != EWOULDBLOCK) c.dead = true;
      return;
    }
    total += static_cast<size_t>(n);
    std::string out;
    c.session->Receive(buffer, static_cast<size_t>(n), RealtimeNowNs(), &out);
    if (!out.empty()) Queue(c, std::make_shared<const std::string>(std::move(out)), false);
    if (c.session->connected() && !c.counted) {
      c.counted = true;
      log::Debug("vrpn: client {} connected", SockaddrToString(c.peer));
      std::lock_guard<std::mutex> lock(stats_mutex_);
      ++stats_.connections;
    }
    if (c.session->closed()) {
      if (c.session->close_reason() != "client disconnected") {
        log::Debug("vrpn: client {} closed: {}", SockaddrToString(c.peer), c.session->close_reason());
        std::lock_guard<std::mutex> lock(stats_mutex_);
        ++stats_.refused;
      }
      Flush(c);
      c.dead = true;
    }
  }
}

void VrpnServer::Queue(Client& c, std::shared_ptr<const std::string> bytes, bool droppable) {
  if (droppable && c.queued_bytes > 0 && c.queued_bytes + bytes->size() > options_.client_frame_bytes) {
    std::lock_guard<std::mutex> lock(stats_mutex_);
    ++stats_.frames_dropped;
    return;
  }
  c.queued_bytes += bytes->size();
  c.queue.push_back(std::move(bytes));
  if (c.queued_bytes > options_.client_reply_bytes) {
    log::Warn("vrpn: client {} does not read; closed", SockaddrToString(c.peer));
    c.dead = true;
    return;
  }
  Flush(c);
}

void VrpnServer::Flush(Client& c) {
  while (!c.queue.empty() && !c.connecting) {
    const std::string& front = *c.queue.front();
    const ssize_t n = send(c.fd, front.data() + c.front_sent, front.size() - c.front_sent, MSG_NOSIGNAL | MSG_DONTWAIT);
    if (n < 0) {
      if (errno == EINTR) continue;
      if (errno != EAGAIN && errno != EWOULDBLOCK) c.dead = true;
      return;
    }
    c.front_sent += static_cast<size_t>(n);
    if (c.front_sent < front.size()) return;
    c.queued_bytes -= front.size();
    c.front_sent = 0;
    c.queue.pop_front();
  }
}

void VrpnServer::SendFrame(const pipeline::LiveFrame& frame, bool on_publish) {
  const uint64_t began_ns = RealtimeNowNs();
  const uint64_t stamp_ns = frame.trigger_time_ns ? frame.trigger_time_ns : frame.publish_ns;
  const Timestamp time = FromNs(stamp_ns);
  std::string bytes;
  uint64_t reports = 0;
  for (const pipeline::LiveBody& b : frame.bodies) {
    const size_t i = b.id - 1;
    if (!b.tracked || b.id == 0 || i >= trackers_.size()) continue;
    const Eigen::Vector3d position = b.position * kMetresPerMm;
    bytes += Message(kPosQuat, static_cast<int32_t>(i), time, PosQuatPayload(position, b.orientation),
                     static_cast<uint32_t>(frame.frame_number));
    ++reports;
    LastPose& last = last_[i];
    if (options_.velocity && last.valid && stamp_ns > last.time_ns) {
      const double dt = static_cast<double>(stamp_ns - last.time_ns) * 1e-9;
      bytes += Message(kVelocity, static_cast<int32_t>(i), time,
                       VelocityPayload((position - last.position) / dt, b.orientation * last.orientation.inverse(), dt),
                       static_cast<uint32_t>(frame.frame_number));
      ++reports;
    }
    last = LastPose{true, stamp_ns, position, b.orientation};
  }
  if (bytes.empty()) return;
  const auto shared = std::make_shared<const std::string>(std::move(bytes));
  uint64_t sent = 0;
  for (auto& c : clients_) {
    if (c->dead || !c->session->connected()) continue;
    Queue(*c, shared, true);
    ++sent;
  }
  const uint64_t done_ns = RealtimeNowNs();
  std::lock_guard<std::mutex> lock(stats_mutex_);
  if (sent) latency_.Add(frame.publish_ns, began_ns, done_ns);
  ++stats_.frames;
  stats_.frames_on_publish += on_publish;
  stats_.reports += reports * sent;
}

void VrpnServer::CloseDead() {
  size_t kept = 0;
  for (auto& c : clients_) {
    if (c->dead) {
      close(c->fd);
      continue;
    }
    clients_[kept++] = std::move(c);
  }
  clients_.resize(kept);
  std::lock_guard<std::mutex> lock(stats_mutex_);
  stats_.clients = kept;
}

}  // namespace mocap::stream::vrpn

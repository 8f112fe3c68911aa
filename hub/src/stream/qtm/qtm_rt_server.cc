// The RT server's sockets and thread (see qtm_rt_server.h).
#include "stream/qtm/qtm_rt_server.h"

#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <deque>
#include <map>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "ingest/udp_socket.h"
#include "io/calibration_json.h"
#include "labels/marker_set.h"
#include "util/log.h"

namespace mocap::stream::qtm {
namespace {

constexpr int kIdlePollMs = 100;        // silence is noticed within this
constexpr size_t kReadChunk = 16 * 1024;
constexpr size_t kMaxReadPerTurn = 64 * 1024;  // one chatty client cannot starve the others
constexpr size_t kMaxDatagram = 65507;
// A client being closed (Quit, unframeable bytes) gets this long to take its last answers.
constexpr uint64_t kClosingGraceNs = 2'000'000'000;

uint64_t SteadyNowNs() {
  return static_cast<uint64_t>(std::chrono::duration_cast<std::chrono::nanoseconds>(
                                   std::chrono::steady_clock::now().time_since_epoch())
                                   .count());
}

void SetNonBlocking(int fd) { fcntl(fd, F_SETFL, fcntl(fd, F_GETFL, 0) | O_NONBLOCK); }

std::runtime_error SocketError(const std::string& what) {
  return std::runtime_error("Qualisys RT: " + what + ": " + std::strerror(errno));
}

}  // namespace

struct QtmRtServer::Client {
  int fd = -1;
  sockaddr_in peer{};
  std::unique_ptr<RtSession> session;
  std::deque<PacketPtr> queue;
  size_t queued_bytes = 0;
  size_t front_sent = 0;   // bytes of queue.front() already written
  bool closing = false;    // close once the queue is written (nothing more is read)
  uint64_t closing_since_ns = 0;
  bool dead = false;       // close now
};

RtSystem LoadRtSystem(const std::string& calibration_path, double rate_hz, const std::string& bodies_file,
                      const std::string& labels_file) {
  RtSystem system;
  system.rate_hz = rate_hz;
  system.rig = LoadRigJson(calibration_path);
  system.axis_upwards = AxisUpwards(system.rig);
  if (!bodies_file.empty()) system.bodies = ReadBodiesFile(bodies_file);
  if (!labels_file.empty()) system.label_names = ReadMarkerSetFile(labels_file).names;
  return system;
}

void QtmRtOptions::Check() const {
  ParseHostPort(listen);
  if (max_clients == 0) throw std::invalid_argument("qtm-rt: max clients must be > 0");
  if (client_frame_bytes == 0 || client_reply_bytes < client_frame_bytes)
    throw std::invalid_argument("qtm-rt: client queue bounds must be > 0, answers' at least the frames'");
  if (client_socket_bytes < 4096) throw std::invalid_argument("qtm-rt: client socket buffer must be >= 4096 bytes");
  if (queue_frames == 0) throw std::invalid_argument("qtm-rt: queue must hold at least one frame");
  if (!(silence_s > 0.0)) throw std::invalid_argument("qtm-rt: silence must be > 0 s");
}

QtmRtServer::QtmRtServer(QtmRtOptions options, RtSystem system)
    : options_((options.Check(), std::move(options))), queue_(options_.queue_frames, "Qualisys RT") {
  state_.system = std::move(system);
  if (!state_.system.label_names.empty())
    state_.names.UseMarkerSet(std::make_shared<const std::vector<std::string>>(state_.system.label_names));
  const HostPort where = ParseHostPort(options_.listen);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_port = htons(where.port);
  if (where.host.empty() || where.host == "*") addr.sin_addr.s_addr = htonl(INADDR_ANY);
  else addr = ResolveHostPort(where);
  listen_fd_ = socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  if (listen_fd_ < 0) throw SocketError("socket");
  const int one = 1;
  setsockopt(listen_fd_, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
  if (bind(listen_fd_, reinterpret_cast<const sockaddr*>(&addr), sizeof addr) != 0 ||
      listen(listen_fd_, SOMAXCONN) != 0) {
    const std::runtime_error error = SocketError("cannot listen on " + options_.listen);
    close(listen_fd_);
    throw error;
  }
  SetNonBlocking(listen_fd_);
  socklen_t len = sizeof addr;
  getsockname(listen_fd_, reinterpret_cast<sockaddr*>(&addr), &len);
  port_ = ntohs(addr.sin_port);
  udp_fd_ = socket(AF_INET, SOCK_DGRAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
  if (udp_fd_ < 0) {
    const std::runtime_error error = SocketError("udp socket");
    close(listen_fd_);
    throw error;
  }
  thread_ = std::thread([this] { Run(); });
}

QtmRtServer::~QtmRtServer() {
  stop_ = true;
  queue_.Wake();
  if (thread_.joinable()) thread_.join();
  close(listen_fd_);
  close(udp_fd_);
}

void QtmRtServer::Publish(SharedFrame frame) {
  queue_.Push(std::move(frame));
}

QtmRtStats QtmRtServer::stats() const {
  std::lock_guard<std::mutex> lock(stats_mutex_);
  QtmRtStats s = stats_;
  s.queue_dropped = queue_.dropped();
  return s;
}

nlohmann::json QtmRtServer::StatsJson() const {
  const QtmRtStats s = stats();
  return {{"port", port_},           {"clients", s.clients},         {"connections", s.connections},
          {"refused", s.refused},    {"frames", s.frames},           {"packets_sent", s.packets_sent},
          {"frames_dropped", s.frames_dropped}, {"queue_dropped", s.queue_dropped}, {"errors", s.errors},
          {"udp_failures", s.udp_failures}};
}

void QtmRtServer::Run() {
  std::vector<pollfd> fds;
  while (!stop_) {
    fds.clear();
    fds.push_back({listen_fd_, POLLIN, 0});
    fds.push_back({queue_.fd(), POLLIN, 0});
    // A closing client is not read any more: its unread bytes must not wake the loop.
    for (const auto& c : clients_)
      fds.push_back({c->fd, static_cast<short>((c->closing ? 0 : POLLIN) | (c->queue.empty() ? 0 : POLLOUT)), 0});
    if (poll(fds.data(), fds.size(), kIdlePollMs) < 0 && errno != EINTR) {
      log::Error("Qualisys RT: poll failed: {}", std::strerror(errno));
      break;
    }
    if (fds[1].revents & POLLIN) queue_.Acknowledge();
    TakeFrames();
    TakeCaptureState();
    // Clients accepted in this turn are not in fds yet: only the first fds.size() - 2 are polled.
    const size_t polled = fds.size() - 2;
    for (size_t i = 0; i < polled && i < clients_.size(); ++i) {
      Client& c = *clients_[i];
      const short revents = fds[i + 2].revents;
      if ((revents & (POLLERR | POLLNVAL)) || (c.closing && (revents & POLLHUP))) c.dead = true;
      if (!c.dead && (revents & (POLLIN | POLLHUP))) Read(c);
      if (!c.dead && (revents & POLLOUT)) Flush(c);
    }
    if (fds[0].revents & POLLIN) Accept();
    const uint64_t now = SteadyNowNs();
    for (auto& c : clients_)
      if (c->closing && now - c->closing_since_ns > kClosingGraceNs) c->dead = true;
    if (state_.flowing && now - last_frame_ns_ > static_cast<uint64_t>(options_.silence_s * 1e9)) {
      state_.flowing = false;
      Broadcast(RtEvent::kConnectionClosed);
    }
    CloseDead();
  }
  // Tell whoever listens, without waiting for anyone.
  for (auto& c : clients_) {
    RtOutput out;
    out.tcp.push_back({std::make_shared<const std::string>(MakeEventPacket(RtEvent::kQtmShuttingDown)), false});
    Deliver(*c, out);
    close(c->fd);
  }
  clients_.clear();
}

void QtmRtServer::Accept() {
  // Bounded per turn so a connection storm cannot keep frames from going out.
  for (int i = 0; i < 256; ++i) {
    sockaddr_in peer{};
    socklen_t len = sizeof peer;
    const int fd = accept4(listen_fd_, reinterpret_cast<sockaddr*>(&peer), &len, SOCK_NONBLOCK | SOCK_CLOEXEC);
    if (fd < 0) {
      if (errno != EAGAIN && errno != EWOULDBLOCK && errno != EINTR && errno != ECONNABORTED)
        log::Warn("Qualisys RT: accept failed: {}", std::strerror(errno));
      return;
    }
    if (clients_.size() >= options_.max_clients) {
      {
        std::lock_guard<std::mutex> lock(stats_mutex_);
        ++stats_.refused;
      }
      const std::string refusal =
          MakeStringPacket(PacketType::kError, "Connection refused. Max number of clients reached.");
      (void)!send(fd, refusal.data(), refusal.size(), MSG_NOSIGNAL | MSG_DONTWAIT);
      close(fd);
      continue;
    }
    const int one = 1;
    setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
    setsockopt(fd, SOL_SOCKET, SO_SNDBUF, &options_.client_socket_bytes, sizeof options_.client_socket_bytes);
    auto client = std::make_unique<Client>();
    client->fd = fd;
    client->peer = peer;
    RtOutput out;
    client->session = std::make_unique<RtSession>(peer, &out);
    Deliver(*client, out);
    log::Debug("Qualisys RT: client {} connected", SockaddrToString(peer));
    clients_.push_back(std::move(client));
    std::lock_guard<std::mutex> lock(stats_mutex_);
    ++stats_.connections;
    stats_.clients = clients_.size();
  }
}

void QtmRtServer::Read(Client& c) {
  uint8_t buffer[kReadChunk];
  size_t total = 0;
  while (total < kMaxReadPerTurn && !c.closing && !c.dead) {
    const ssize_t n = recv(c.fd, buffer, sizeof buffer, 0);
    if (n == 0) {
      c.dead = true;  // the client closed: nothing more can reach it
      return;
    }
    if (n < 0) {
      if (errno == EINTR) continue;
      if (errno != EAGAIN && errno != EWOULDBLOCK) c.dead = true;
      return;
    }
    total += static_cast<size_t>(n);
    RtOutput out;
    const uint64_t errors_before = c.session->errors();
    c.session->Receive(buffer, static_cast<size_t>(n), state_, &out);
    if (c.session->errors() != errors_before) {
      std::lock_guard<std::mutex> lock(stats_mutex_);
      stats_.errors += c.session->errors() - errors_before;
    }
    Deliver(c, out);
  }
}

void QtmRtServer::Deliver(Client& c, RtOutput& out) {
  uint64_t sent = 0, dropped = 0, udp_failed = 0;
  for (RtOutPacket& p : out.tcp) {
    // An empty queue always takes the frame, so no frame is too large for everyone.
    if (p.droppable && c.queued_bytes > 0 && c.queued_bytes + p.bytes->size() > options_.client_frame_bytes) {
      ++dropped;
      continue;
    }
    c.queued_bytes += p.bytes->size();
    c.queue.push_back(std::move(p.bytes));
    if (p.droppable) ++sent;
  }
  for (const PacketPtr& p : out.udp) {
    const sockaddr_in& to = c.session->udp_target();
    if (p->size() <= kMaxDatagram &&
        sendto(udp_fd_, p->data(), p->size(), MSG_DONTWAIT | MSG_NOSIGNAL, reinterpret_cast<const sockaddr*>(&to),
               sizeof to) == static_cast<ssize_t>(p->size()))
      ++sent;
    else
      ++udp_failed;
  }
  if (out.close && !c.closing) {
    c.closing = true;
    c.closing_since_ns = SteadyNowNs();
  }
  if (c.queued_bytes > options_.client_reply_bytes) {
    log::Warn("Qualisys RT: client {} does not read its answers; closed", SockaddrToString(c.peer));
    c.dead = true;
  }
  if (!c.dead) Flush(c);
  if (sent || dropped || udp_failed) {
    std::lock_guard<std::mutex> lock(stats_mutex_);
    stats_.packets_sent += sent;
    stats_.frames_dropped += dropped;
    stats_.udp_failures += udp_failed;
  }
}

void QtmRtServer::Flush(Client& c) {
  while (!c.queue.empty()) {
    const std::string& front = *c.queue.front();
    const ssize_t n = send(c.fd, front.data() + c.front_sent, front.size() - c.front_sent, MSG_NOSIGNAL | MSG_DONTWAIT);
    if (n < 0) {
      if (errno == EINTR) continue;
      if (errno != EAGAIN && errno != EWOULDBLOCK) c.dead = true;  // vanished mid-frame: gone
      return;
    }
    c.front_sent += static_cast<size_t>(n);
    if (c.front_sent < front.size()) return;
    c.queued_bytes -= front.size();
    c.front_sent = 0;
    c.queue.pop_front();
  }
  if (c.closing) c.dead = true;
}

void QtmRtServer::TakeFrames() {
  while (SharedFrame frame = queue_.PopNow()) {
    last_frame_ns_ = SteadyNowNs();
    state_.names.Update(*frame);
    state_.latest = frame;
    if (!state_.flowing) {
      state_.flowing = true;
      Broadcast(RtEvent::kConnected);
    }
    std::map<uint32_t, PacketPtr> encoded;  // one encoding per component mask per frame
    const int cameras = static_cast<int>(state_.system.rig.cameras.size());
    const RtEncoder encode = [&](uint32_t components) {
      PacketPtr& p = encoded[components];
      if (!p) p = std::make_shared<const std::string>(EncodeDataPacket(*frame, components, state_.names, cameras));
      return p;
    };
    for (auto& c : clients_) {
      if (c->dead) continue;
      RtOutput out;
      c->session->OnFrame(state_, encode, &out);
      Deliver(*c, out);
    }
    std::lock_guard<std::mutex> lock(stats_mutex_);
    ++stats_.frames;
  }
}

void QtmRtServer::OnCapture(const pipeline::CaptureEvent& event) {
  const int state = event.kind == pipeline::CaptureEvent::Kind::kStarted ? 2 : 1;
  if (capture_state_.exchange(state) != state) queue_.Wake();
}

void QtmRtServer::TakeCaptureState() {
  const int state = capture_state_.load();
  if (state == 0 || (state == 2) == state_.capturing) return;
  state_.capturing = state == 2;
  Broadcast(state_.capturing ? RtEvent::kCaptureStarted : RtEvent::kCaptureStopped);
}

void QtmRtServer::Broadcast(RtEvent event) {
  for (auto& c : clients_) {
    if (c->dead) continue;
    RtOutput out;
    c->session->OnEvent(event, &out);
    Deliver(*c, out);
  }
}

void QtmRtServer::CloseDead() {
  size_t kept = 0;
  for (auto& c : clients_) {
    if (c->dead) {
      log::Debug("Qualisys RT: client {} gone", SockaddrToString(c->peer));
      close(c->fd);
      continue;
    }
    clients_[kept++] = std::move(c);
  }
  if (kept == clients_.size()) return;
  clients_.resize(kept);
  std::lock_guard<std::mutex> lock(stats_mutex_);
  stats_.clients = kept;
}

}  // namespace mocap::stream::qtm

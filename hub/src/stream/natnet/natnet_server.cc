// The NatNet server's socket and thread (see natnet_server.h).
#include "stream/natnet/natnet_server.h"
#include "stream/publish_latency.h"

#include <arpa/inet.h>
#include <poll.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "util/log.h"

namespace mocap::stream::natnet {
namespace {

constexpr int kIdlePollMs = 100;
constexpr int kMaxRequestsPerTurn = 256;  // a request flood cannot keep frames from going out

bool SameAddress(const sockaddr_in& a, const sockaddr_in& b) {
  return a.sin_addr.s_addr == b.sin_addr.s_addr && a.sin_port == b.sin_port;
}

}  // namespace

void NatNetOptions::Check() const {
  ParseHostPort(listen);
  if (!multicast.empty()) {
    in_addr group{};
    if (inet_pton(AF_INET, multicast.c_str(), &group) != 1 || !IN_MULTICAST(ntohl(group.s_addr)))
      throw std::invalid_argument("natnet: multicast group '" + multicast + "' is not an IPv4 multicast address");
  }
  if (data_port == 0) throw std::invalid_argument("natnet: data port must be 1-65535");
  if (multicast_ttl < 1 || multicast_ttl > 255) throw std::invalid_argument("natnet: multicast TTL must be 1-255");
  Version v;
  if (!ParseVersion(version, &v) || !Supported(v))
    throw std::invalid_argument("natnet: bitstream version '" + version + "' is not one of 3.0, 3.1, 4.0, 4.1");
  if (max_clients == 0) throw std::invalid_argument("natnet: max clients must be > 0");
  if (!(client_timeout_s > 0.0)) throw std::invalid_argument("natnet: client timeout must be > 0 s");
  if (queue_frames == 0) throw std::invalid_argument("natnet: queue must hold at least one frame");
}

NatNetServer::NatNetServer(NatNetOptions options, Model model)
    : options_((options.Check(), std::move(options))), model_(std::move(model)), queue_(options_.queue_frames, "natnet") {
  socket_.Bind(ParseHostPort(options_.listen));
  ParseVersion(options_.version, &state_.version);
  state_.info.version = state_.version;
  state_.info.data_port = options_.data_port;
  multicast_ = !options_.multicast.empty();
  state_.info.multicast = multicast_;
  if (multicast_) {
    socket_.EnableMulticast(options_.multicast_ttl);
    group_.sin_family = AF_INET;
    group_.sin_port = htons(options_.data_port);
    inet_pton(AF_INET, options_.multicast.c_str(), &group_.sin_addr);
    std::memcpy(state_.info.multicast_group, &group_.sin_addr.s_addr, 4);
  } else {
    std::memset(state_.info.multicast_group, 0, 4);
  }
  thread_ = std::thread([this] { Run(); });
}

NatNetServer::~NatNetServer() {
  stop_ = true;
  queue_.Wake();
  if (thread_.joinable()) thread_.join();
}

void NatNetServer::Publish(SharedFrame frame) {
  // Never waits: while the thread holds the sockets (answering requests) the frame queues for it.
  std::unique_lock<std::mutex> lock(send_mutex_, std::try_to_lock);
  if (lock.owns_lock() && (multicast_ || clients_.size() <= options_.inline_clients)) {
    SendQueued();
    latest_ = frame;
    Send(*frame, true);
    return;
  }
  if (lock.owns_lock()) lock.unlock();
  queue_.Push(std::move(frame));
}

void NatNetServer::SendQueued() {
  while (SharedFrame frame = queue_.PopNow()) {
    latest_ = frame;
    Send(*frame, false);
  }
}

NatNetStats NatNetServer::stats() const {
  std::lock_guard<std::mutex> lock(stats_mutex_);
  NatNetStats s = stats_;
  s.frames_dropped = queue_.dropped();
  return s;
}

nlohmann::json NatNetServer::StatsJson() const {
  const NatNetStats s = stats();
  std::lock_guard<std::mutex> lock(stats_mutex_);
  nlohmann::json out = {{"port", port()},
          {"multicast", options_.multicast.empty() ? "" : options_.multicast + ":" + std::to_string(options_.data_port)},
          {"clients", s.clients},
          {"requests", s.requests},
          {"refused", s.refused},
          {"frames", s.frames},
          {"frames_on_publish", s.frames_on_publish},
          {"datagrams", s.datagrams},
          {"send_failures", s.send_failures},
          {"frames_dropped", s.frames_dropped},
          {"points_dropped", s.points_dropped}};
  out.update(latency_.Json("NatNet datagram"));
  return out;
}

void NatNetServer::Run() {
  while (!stop_) {
    pollfd fds[2] = {{socket_.fd(), POLLIN, 0}, {queue_.fd(), POLLIN, 0}};
    if (poll(fds, 2, kIdlePollMs) < 0 && errno != EINTR) {
      log::Error("natnet: poll failed: {}", std::strerror(errno));
      break;
    }
    std::lock_guard<std::mutex> lock(send_mutex_);
    if (fds[1].revents & POLLIN) queue_.Acknowledge();
    SendQueued();
    Serve(RealtimeNowNs());
  }
}

void NatNetServer::Serve(uint64_t now_ns) {
  Datagram d;
  uint64_t requests = 0, refused = 0, points_dropped = 0;
  for (int i = 0; i < kMaxRequestsPerTurn && socket_.Receive(&d, 0); ++i) {
    ++requests;
    const Request request = ParseRequest(d.bytes.data(), d.bytes.size());
    if (!request.ok) log::Debug("natnet: bad request from {}: {}", d.FromString(), request.reason);
    Reply reply = Answer(request, model_, &state_);
    refused += reply.failed;
    if (reply.subscription == Subscription::kSubscribe && !multicast_ &&
        clients_.size() >= options_.max_clients) {
      bool known = false;
      for (const Client& c : clients_) known |= SameAddress(c.address, d.from);
      if (!known) {
        reply.packet = EncodeMessageString("mocap-hub: " + std::to_string(options_.max_clients) +
                                           " unicast clients already; not streaming to this one");
        reply.subscription = Subscription::kNone;
        ++refused;
      }
    }
    Subscribe(d.from, reply.subscription, now_ns);
    if (!reply.packet.empty())
      socket_.SendTo(d.from, reinterpret_cast<const uint8_t*>(reply.packet.data()), reply.packet.size());
    if (reply.send_frame && latest_) {
      const std::string frame = EncodeLatest(&points_dropped);
      socket_.SendTo(d.from, reinterpret_cast<const uint8_t*>(frame.data()), frame.size());
    }
  }
  const uint64_t timeout_ns = static_cast<uint64_t>(options_.client_timeout_s * 1e9);
  size_t kept = 0;
  for (Client& c : clients_)
    if (now_ns < c.last_seen_ns + timeout_ns) clients_[kept++] = c;
  clients_.resize(kept);
  std::lock_guard<std::mutex> lock(stats_mutex_);
  stats_.requests += requests;
  stats_.refused += refused;
  stats_.points_dropped += points_dropped;
  stats_.clients = clients_.size();
}

void NatNetServer::Subscribe(const sockaddr_in& from, Subscription what, uint64_t now_ns) {
  if (multicast_ || what == Subscription::kNone) return;
  for (size_t i = 0; i < clients_.size(); ++i) {
    if (!SameAddress(clients_[i].address, from)) continue;
    if (what == Subscription::kUnsubscribe)
      clients_.erase(clients_.begin() + static_cast<std::ptrdiff_t>(i));
    else
      clients_[i].last_seen_ns = now_ns;
    return;
  }
  // A keep-alive from a client that was forgotten (or never connected) subscribes it again.
  if (what != Subscription::kUnsubscribe && clients_.size() < options_.max_clients)
    clients_.push_back({from, now_ns});
}

std::string NatNetServer::EncodeLatest(uint64_t* points_dropped) {
  return EncodeFrame(*latest_, model_, state_.version, FrameStamps{RealtimeNowNs()}, points_dropped);
}

void NatNetServer::Send(const pipeline::LiveFrame& frame, bool on_publish) {
  const uint64_t began_ns = RealtimeNowNs();
  uint64_t points_dropped = 0;
  const std::string packet = EncodeLatest(&points_dropped);
  const auto* bytes = reinterpret_cast<const uint8_t*>(packet.data());
  uint64_t sent = 0, failed = 0;
  if (multicast_)
    (socket_.SendTo(group_, bytes, packet.size()) ? sent : failed)++;
  else
    for (const Client& c : clients_) (socket_.SendTo(c.address, bytes, packet.size()) ? sent : failed)++;
  const uint64_t done_ns = RealtimeNowNs();
  std::lock_guard<std::mutex> lock(stats_mutex_);
  if (sent) latency_.Add(frame.publish_ns, began_ns, done_ns);
  if (sent) ++stats_.frames;
  if (sent && on_publish) ++stats_.frames_on_publish;
  stats_.datagrams += sent;
  stats_.send_failures += failed;
  stats_.points_dropped += points_dropped;
}

}  // namespace mocap::stream::natnet

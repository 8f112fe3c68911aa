// The UDP stream's thread (see udp_stream_server.h).
#include "stream/udp_stream_server.h"
#include "stream/publish_latency.h"

#include <arpa/inet.h>
#include <sys/socket.h>

#include <algorithm>
#include <map>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "util/log.h"

namespace mocap::stream {
namespace {

// How long the thread waits for a frame before it looks at requests again: subscriptions are
// served within this even when no frames flow.
constexpr std::chrono::milliseconds kIdleWait{20};

}  // namespace

void UdpStreamOptions::Check() const {
  ParseHostPort(listen);
  if (!multicast.empty()) {
    const HostPort group = ParseHostPort(multicast);
    in_addr addr{};
    if (inet_pton(AF_INET, group.host.c_str(), &addr) != 1 || !IN_MULTICAST(ntohl(addr.s_addr)) || group.port == 0)
      throw std::invalid_argument("stream multicast '" + multicast + "' is not a multicast GROUP:PORT (224.0.0.0/4)");
  }
  if (multicast_parts == 0 || (multicast_parts & ~kAllParts))
    throw std::invalid_argument("stream multicast parts must be points, bodies and/or labels");
  if (multicast_ttl < 1 || multicast_ttl > 255) throw std::invalid_argument("stream multicast TTL must be 1-255");
  if (max_subscribers == 0) throw std::invalid_argument("stream max subscribers must be > 0");
  if (!(subscription_s > 0.0)) throw std::invalid_argument("stream subscription lifetime must be > 0");
  if (queue_frames == 0) throw std::invalid_argument("stream queue must hold at least one frame");
  guard.Check();
}

UdpStreamServer::UdpStreamServer(UdpStreamOptions options)
    : options_((options.Check(), std::move(options))),
      queue_(options_.queue_frames),
      table_(options_.max_subscribers, static_cast<uint64_t>(options_.subscription_s * 1e9)),
      guard_(options_.guard) {
  socket_.Bind(ParseHostPort(options_.listen));
  if (!options_.multicast.empty()) {
    socket_.EnableMulticast(options_.multicast_ttl);
    multicast_ = ResolveHostPort(ParseHostPort(options_.multicast));
    has_multicast_ = true;
  }
  thread_ = std::thread([this] { Run(); });
}

UdpStreamServer::~UdpStreamServer() {
  stop_ = true;
  queue_.Close();
  if (thread_.joinable()) thread_.join();
}

UdpStreamStats UdpStreamServer::stats() const {
  std::lock_guard<std::mutex> lock(stats_mutex_);
  UdpStreamStats s = stats_;
  s.frames_dropped = queue_.dropped();
  return s;
}

nlohmann::json UdpStreamServer::StatsJson() const {
  const UdpStreamStats s = stats();
  nlohmann::json out = {{"port", port()},
          {"multicast", options_.multicast},
          {"subscribers", s.subscribers},
          {"frames", s.frames},
          {"datagrams", s.datagrams},
          {"send_failures", s.send_failures},
          {"frames_dropped", s.frames_dropped},
          {"bad_requests", s.bad_requests},
          {"challenges", s.challenges},
          {"unproven", s.unproven},
          {"rate_limited", s.rate_limited},
          {"points_dropped", s.points_dropped}};
  std::lock_guard<std::mutex> lock(stats_mutex_);
  out.update(latency_.Json("datagram"));
  return out;
}

void UdpStreamServer::Publish(SharedFrame frame) {
  // Never waits: while the sending thread holds the table (serving requests) the frame queues.
  std::unique_lock<std::mutex> lock(table_mutex_, std::try_to_lock);
  if (lock.owns_lock() && table_.subscribers().size() + (has_multicast_ ? 1 : 0) <= options_.inline_subscribers) {
    Send(*frame);
    return;
  }
  if (lock.owns_lock()) lock.unlock();
  queue_.Push(std::move(frame));
}

void UdpStreamServer::Run() {
  while (!stop_) {
    const SharedFrame frame = queue_.Pop(kIdleWait);
    std::lock_guard<std::mutex> lock(table_mutex_);
    ServeRequests(RealtimeNowNs());
    if (frame) Send(*frame);
  }
}

void UdpStreamServer::ServeRequests(uint64_t now_ns) {
  Datagram datagram;
  uint64_t bad = 0, challenges = 0, unproven = 0, limited = 0;
  // Bounded per turn: a flood of requests cannot keep frames from going out.
  for (int i = 0; i < 256 && socket_.Receive(&datagram, 0); ++i) {
    const StreamRequest request = DecodeStreamRequest(datagram.bytes.data(), datagram.bytes.size());
    if (!request.ok) {
      ++bad;
      log::Debug("stream: bad request from {}: {}", datagram.FromString(), request.reason);
      continue;
    }
    if (!guard_.Valid(datagram.from, request.cookie, now_ns)) {
      ++unproven;
      // Challenges within the source's rate: past it, nothing is answered.
      if (!guard_.Admit(datagram.from, now_ns)) {
        ++limited;
        continue;
      }
      // A challenge only for a Subscribe at least as large as it: never an amplifier.
      const std::string challenge = EncodeChallenge(guard_.Cookie(datagram.from, now_ns));
      if (request.subscribe && datagram.bytes.size() >= challenge.size() &&
          socket_.SendTo(datagram.from, reinterpret_cast<const uint8_t*>(challenge.data()), challenge.size()))
        ++challenges;
      continue;
    }
    if (!request.subscribe) {
      table_.Unsubscribe(datagram.from);
    } else if (!table_.Subscribe(datagram.from, request.parts, now_ns)) {
      ++bad;
      log::Warn("stream: refused {}: {} subscribers already", datagram.FromString(), options_.max_subscribers);
    }
  }
  table_.Expire(now_ns);
  std::lock_guard<std::mutex> lock(stats_mutex_);
  stats_.bad_requests += bad;
  stats_.challenges += challenges;
  stats_.unproven += unproven;
  stats_.rate_limited += limited;
  stats_.subscribers = table_.subscribers().size();
}

void UdpStreamServer::Send(const pipeline::LiveFrame& frame) {
  const uint64_t began_ns = RealtimeNowNs();
  std::map<uint32_t, EncodedFrame> encoded;  // one encoding per distinct set of parts
  auto message = [&](uint32_t parts) -> const EncodedFrame& {
    auto it = encoded.find(parts);
    if (it == encoded.end()) it = encoded.emplace(parts, EncodeStreamFrame(frame, parts)).first;
    return it->second;
  };
  uint64_t sent = 0, failed = 0;
  auto send = [&](const sockaddr_in& to, const EncodedFrame& m) {
    if (socket_.SendTo(to, reinterpret_cast<const uint8_t*>(m.bytes.data()), m.bytes.size()))
      ++sent;
    else
      ++failed;
  };
  for (const StreamSubscriber& s : table_.subscribers()) send(s.address, message(s.parts));
  if (has_multicast_) send(multicast_, message(options_.multicast_parts));
  uint32_t points_dropped = 0;
  for (const auto& [parts, m] : encoded) points_dropped = std::max(points_dropped, m.points_dropped);
  const uint64_t done_ns = RealtimeNowNs();
  std::lock_guard<std::mutex> lock(stats_mutex_);
  if (sent) latency_.Add(frame.publish_ns, began_ns, done_ns);
  if (sent) ++stats_.frames;
  stats_.datagrams += sent;
  stats_.send_failures += failed;
  stats_.points_dropped += points_dropped;
}

}  // namespace mocap::stream

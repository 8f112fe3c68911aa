// The probe's amplifier, as an attacker sends it: subscriptions with a forged source address
// (a raw socket on loopback, the victim at 127.0.0.9) while frames are published. The victim
// gets no frame, and no more bytes than the attacker sent (at most a challenge per request,
// within the per-source rate). Needs CAP_NET_RAW; skipped, saying so, without it.
#include <arpa/inet.h>
#include <netinet/ip.h>
#include <netinet/udp.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <thread>

#include <gtest/gtest.h>

#include "mocap_stream.pb.h"
#include "stream/udp_stream_server.h"

namespace mocap::stream {
namespace {

// One UDP datagram from `from` (any address on loopback) to 127.0.0.1:port.
bool SendForged(int raw, const sockaddr_in& from, uint16_t port, const std::string& payload) {
  std::vector<uint8_t> packet(sizeof(iphdr) + sizeof(udphdr) + payload.size());
  auto* ip = reinterpret_cast<iphdr*>(packet.data());
  ip->version = 4;
  ip->ihl = 5;
  ip->ttl = 64;
  ip->protocol = IPPROTO_UDP;
  ip->saddr = from.sin_addr.s_addr;
  ip->daddr = htonl(INADDR_LOOPBACK);
  ip->tot_len = htons(static_cast<uint16_t>(packet.size()));  // the kernel fills the checksum
  auto* udp = reinterpret_cast<udphdr*>(packet.data() + sizeof(iphdr));
  udp->source = from.sin_port;
  udp->dest = htons(port);
  udp->len = htons(static_cast<uint16_t>(sizeof(udphdr) + payload.size()));
  udp->check = 0;  // none (IPv4)
  std::memcpy(packet.data() + sizeof(iphdr) + sizeof(udphdr), payload.data(), payload.size());
  sockaddr_in to{};
  to.sin_family = AF_INET;
  to.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  return sendto(raw, packet.data(), packet.size(), 0, reinterpret_cast<const sockaddr*>(&to), sizeof to) ==
         static_cast<ssize_t>(packet.size());
}

TEST(StreamSpoofing, AForgedSubscriptionSendsTheVictimNoFrame) {
  const int raw = socket(AF_INET, SOCK_RAW, IPPROTO_RAW);
  if (raw < 0) GTEST_SKIP() << "no raw socket (" << std::strerror(errno) << "): needs CAP_NET_RAW";
  UdpStreamOptions options;
  options.listen = "127.0.0.1:0";
  UdpStreamServer server(options);
  UdpSocket victim;
  victim.Bind({"127.0.0.9", 0});
  sockaddr_in forged{};
  forged.sin_family = AF_INET;
  inet_pton(AF_INET, "127.0.0.9", &forged.sin_addr);
  forged.sin_port = htons(victim.port());

  // The probe's 256 forged subscriptions, first requests and made-up cookies, then frames.
  size_t forged_bytes = 0;
  for (int i = 0; i < 256; ++i) {
    const std::string request =
        i % 2 ? EncodeSubscribe(kPartPoints | kPartBodies, std::string(16, static_cast<char>(i))) : EncodeSubscribe(kPartPoints);
    ASSERT_TRUE(SendForged(raw, forged, server.port(), request));
    forged_bytes += request.size();
  }
  close(raw);
  for (int i = 0; i < 100 && server.stats().unproven < 256; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(5));
  ASSERT_EQ(server.stats().unproven, 256u) << "the forged datagrams did not all arrive";
  for (uint64_t n = 1; n <= 100; ++n) {
    service::LiveFrame f;
    f.frame_number = n;
    f.publish_ns = RealtimeNowNs();
    f.points.resize(50);
    server.Publish(ShareFrame(f));
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  size_t datagrams = 0, bytes = 0, frames = 0;
  Datagram d;
  while (victim.Receive(&d, 100)) {
    ++datagrams;
    bytes += d.bytes.size();
    v1::StreamFrame message;
    ASSERT_TRUE(message.ParseFromArray(d.bytes.data(), static_cast<int>(d.bytes.size())));
    if (message.subscribe_cookie().empty()) ++frames;
  }
  std::printf("256 forged subscriptions (%zu bytes) during 100 frames: the victim got %zu datagrams, %zu bytes "
              "(amplification %.2f), %zu frames; subscribers %zu\n",
              forged_bytes, datagrams, bytes, static_cast<double>(bytes) / static_cast<double>(forged_bytes), frames,
              server.stats().subscribers);
  EXPECT_EQ(frames, 0u);
  EXPECT_EQ(server.stats().subscribers, 0u);
  EXPECT_LE(bytes, forged_bytes / 2);  // only the first requests are answered, none larger than itself
}

}  // namespace
}  // namespace mocap::stream

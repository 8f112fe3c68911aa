// The authenticated envelope, hub side: sealing and parsing agree with the documented layout,
// every changed byte breaks the tag, malformed headers are refused with a reason, counters only
// go up, and the replay window refuses duplicates, old and far-off counters while tolerating
// reordering.
#include <gtest/gtest.h>

#include <numeric>
#include <vector>

#include "wire/datagram_envelope.h"
#include "wire/limits.h"
#include "wire/replay_window.h"

namespace mocap::wire {
namespace {

constexpr uint64_t kNow = 1'700'000'000'000'000'000ull;

WireKey KeyOf(uint8_t seed) {
  WireKey k;
  for (size_t i = 0; i < k.size(); ++i) k[i] = static_cast<uint8_t>(seed + 7 * i);
  return k;
}

TEST(Envelope, SealsTheDocumentedLayoutAndVerifies) {
  InitSodium();
  std::vector<uint8_t> payload(kMaxPacketBytes);
  std::iota(payload.begin(), payload.end(), uint8_t{0});
  EnvelopeHeader h;
  h.direction = Direction::kToNode;
  h.key_id = 3;
  h.node_id = 4095;
  h.counter = 0x0102030405060708ull;
  const std::vector<uint8_t> d = SealEnvelope(h, KeyOf(1), payload.data(), payload.size());
  ASSERT_EQ(d.size(), kMaxDatagramBytes);
  EXPECT_EQ(d[0], kEnvelopeMagic);
  EXPECT_EQ(d[1], 1);
  EXPECT_EQ(d[2], 3);
  EXPECT_EQ(d[3], 0);
  EXPECT_EQ(d[4], 0xff);
  EXPECT_EQ(d[5], 0x0f);
  EXPECT_EQ(d[8], 0x08);
  EXPECT_EQ(d[15], 0x01);
  const ParsedEnvelope p = ParseEnvelope(d.data(), d.size());
  ASSERT_TRUE(p.ok) << p.reason;
  EXPECT_EQ(p.header.direction, Direction::kToNode);
  EXPECT_EQ(p.header.node_id, 4095u);
  EXPECT_EQ(p.header.counter, h.counter);
  EXPECT_EQ(std::vector<uint8_t>(p.payload, p.payload + p.payload_size), payload);
  EXPECT_TRUE(VerifyEnvelopeTag(d.data(), d.size(), KeyOf(1)));
  EXPECT_FALSE(VerifyEnvelopeTag(d.data(), d.size(), KeyOf(2)));
  std::vector<uint8_t> flipped = d;
  for (size_t i = 0; i < flipped.size(); ++i) {
    flipped[i] ^= 0x01;
    EXPECT_FALSE(VerifyEnvelopeTag(flipped.data(), flipped.size(), KeyOf(1))) << "byte " << i;
    flipped[i] ^= 0x01;
  }
  EXPECT_FALSE(VerifyEnvelopeTag(d.data(), d.size() - 1, KeyOf(1)));
  EXPECT_THROW(SealEnvelope(h, KeyOf(1), payload.data(), kMaxPacketBytes + 1), std::invalid_argument);
  EXPECT_THROW(SealEnvelope(h, KeyOf(1), payload.data(), 0), std::invalid_argument);
  h.key_id = 0;
  EXPECT_THROW(SealEnvelope(h, KeyOf(1), payload.data(), 10), std::invalid_argument);
}

TEST(Envelope, RefusesMalformedHeadersWithAReason) {
  InitSodium();
  const uint8_t payload[] = {0x08, 0x01};
  const std::vector<uint8_t> good = SealEnvelope({Direction::kToHub, 1, 7, 99}, KeyOf(5), payload, sizeof payload);
  const struct {
    size_t offset;
    uint8_t value;
    const char* reason;
  } bad[] = {{0, 0x08, "not an authenticated datagram"},
             {1, 2, "envelope: unknown direction"},
             {2, 0, "envelope: key id 0"},
             {3, 9, "envelope: reserved byte not 0"}};
  for (const auto& b : bad) {
    std::vector<uint8_t> d = good;
    d[b.offset] = b.value;
    const ParsedEnvelope p = ParseEnvelope(d.data(), d.size());
    EXPECT_FALSE(p.ok);
    EXPECT_EQ(p.reason, b.reason);
  }
  std::vector<uint8_t> d = good;
  std::fill(d.begin() + 4, d.begin() + 8, 0);
  EXPECT_EQ(ParseEnvelope(d.data(), d.size()).reason, "envelope: node id 0");
  d = good;
  std::fill(d.begin() + 8, d.begin() + 16, 0);
  EXPECT_EQ(ParseEnvelope(d.data(), d.size()).reason, "envelope: counter 0");
  EXPECT_EQ(ParseEnvelope(good.data(), kEnvelopeOverheadBytes).reason, "envelope too short");
  EXPECT_FALSE(ParseEnvelope(good.data(), 0).ok);
  std::vector<uint8_t> big(kMaxDatagramBytes + 1, 0);
  big[0] = kEnvelopeMagic;
  EXPECT_EQ(ParseEnvelope(big.data(), big.size()).reason, "datagram larger than 1400 bytes");
}

TEST(Envelope, CountersOnlyGoUp) {
  const uint64_t c = NextCounter(0, kNow);
  EXPECT_EQ(c, kNow);
  EXPECT_EQ(NextCounter(c, kNow), c + 1);
  EXPECT_EQ(NextCounter(c, kNow - 5'000'000'000ull), c + 1);  // the clock was set back
  EXPECT_EQ(NextCounter(c, kNow + 10), kNow + 10);
}

TEST(ReplayWindow, RefusesDuplicatesAndOldCountersToleratesReordering) {
  ReplayWindow w(64);
  for (uint64_t i = 1; i <= 200; ++i)
    EXPECT_EQ(w.Accept(kNow + 1000 * (i ^ 1u), kNow), ReplayWindow::Verdict::kAccepted) << i;
  EXPECT_EQ(w.remembered(), 64u);
  for (uint64_t i = 1; i <= 200; ++i)
    EXPECT_EQ(w.Accept(kNow + 1000 * (i ^ 1u), kNow), ReplayWindow::Verdict::kReplayed) << i;
  EXPECT_EQ(w.Accept(kNow + 180'001, kNow), ReplayWindow::Verdict::kAccepted);
  EXPECT_EQ(w.Accept(kNow - kMaxCounterSkewNs - 1, kNow), ReplayWindow::Verdict::kStale);
  EXPECT_EQ(w.Accept(kNow + kMaxCounterSkewNs + 1, kNow), ReplayWindow::Verdict::kFuture);
  EXPECT_EQ(w.Accept(~0ull, kNow), ReplayWindow::Verdict::kFuture);
  // A restarted receiver (empty window) still refuses recorded traffic older than the skew.
  ReplayWindow fresh;
  EXPECT_EQ(fresh.Accept(kNow - 3'000'000'000ull, kNow), ReplayWindow::Verdict::kStale);
  EXPECT_EQ(fresh.Accept(kNow - 1'000'000'000ull, kNow), ReplayWindow::Verdict::kAccepted);
  EXPECT_EQ(fresh.Accept(kNow - 1'000'000'000ull, kNow), ReplayWindow::Verdict::kReplayed);
  EXPECT_STREQ(VerdictName(ReplayWindow::Verdict::kStale), "stale");
}

TEST(ReplayWindow, CheckGivesAcceptsVerdictAndRemembersNothing) {
  ReplayWindow w(4);
  EXPECT_EQ(w.Check(kNow + 10, kNow), ReplayWindow::Verdict::kAccepted);
  EXPECT_EQ(w.Check(kNow + 10, kNow), ReplayWindow::Verdict::kAccepted);  // not remembered
  EXPECT_EQ(w.remembered(), 0u);
  for (uint64_t i = 1; i <= 4; ++i) ASSERT_EQ(w.Accept(kNow + 10 * i, kNow), ReplayWindow::Verdict::kAccepted);
  EXPECT_EQ(w.Check(kNow + 20, kNow), ReplayWindow::Verdict::kReplayed);   // seen
  EXPECT_EQ(w.Check(kNow + 5, kNow), ReplayWindow::Verdict::kReplayed);    // below the full window
  EXPECT_EQ(w.Check(kNow + 45, kNow), ReplayWindow::Verdict::kAccepted);
  EXPECT_EQ(w.Check(kNow - kMaxCounterSkewNs - 1, kNow), ReplayWindow::Verdict::kStale);
  EXPECT_EQ(w.Check(kNow + kMaxCounterSkewNs + 1, kNow), ReplayWindow::Verdict::kFuture);
  EXPECT_EQ(w.remembered(), 4u);
}

}  // namespace
}  // namespace mocap::wire

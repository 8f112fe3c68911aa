// The hub's handling of every datagram (HubService::HandleDatagram, the one loop serve and record
// run, hands each to FrameIngest), without a socket: chunked frames from two nodes sealed under their keys, a duplicate chunk,
// junk (plain and sealed), forged frames, a replayed datagram, a node not in the calibration and a
// lost frame; frame sets assembled, everything bad counted per kind and node, and the capture's
// raw log keeping every good packet as received and nothing else.
#include "ingest/frame_ingest.h"

#include <filesystem>
#include <map>
#include <stdexcept>

#include <gtest/gtest.h>

#include "ingest/camera_frame_testing.h"
#include "ingest/frame_codec.h"
#include "util/temporary_directory_testing.h"
#include "wire/datagram_envelope.h"
#include "wire/key_file.h"

namespace mocap {
namespace {
namespace fs = std::filesystem;

// The nodes' side of the wire: one key per node, written into the hub's keys directory.
class Nodes {
 public:
  explicit Nodes(const fs::path& keys_dir) {
    fs::create_directories(keys_dir);
    for (uint32_t id : {1u, 2u, 9u}) {
      wire::KeyFile f;
      f.node_id = id;
      f.keys.push_back({1, wire::GenerateKey()});
      wire::WriteKeyFile((keys_dir / wire::KeyFileName(id)).string(), f);
      keys_[id] = f.keys[0].key;
    }
  }
  Datagram Seal(uint32_t node, const std::vector<uint8_t>& payload, const wire::WireKey* key = nullptr) {
    counter_ = wire::NextCounter(counter_, RealtimeNowNs());
    return Received(wire::SealEnvelope({wire::Direction::kToHub, 1, node, counter_}, key ? *key : keys_.at(node),
                                       payload.data(), payload.size()));
  }
  static Datagram Received(std::vector<uint8_t> bytes) {
    Datagram d;
    d.bytes = std::move(bytes);
    d.receive_time_ns = RealtimeNowNs();
    return d;
  }

 private:
  std::map<uint32_t, wire::WireKey> keys_;
  uint64_t counter_ = 0;
};

TEST(FrameIngest, AssemblesLogsAndCountsWhatTheNodesSend) {
  const testing::TemporaryDirectory temp("frame_ingest_test");
  const fs::path& dir = temp.path();
  Nodes nodes(dir / "keys");
  WireAuthOptions auth;
  auth.keys_dir = (dir / "keys").string();
  FrameSetAssemblerOptions assembly;
  assembly.rate_hz = 100;
  assembly.deadline_ns = 50'000'000;
  FrameIngest ingest({1, 2}, assembly, auth);

  SessionInfo info;
  info.rate_hz = 100;
  info.camera_ids = {1, 2};
  SessionWriter writer;
  writer.Create((dir / "session").string(), info);

  std::vector<FrameSet> sets;
  const auto take = [&sets](std::vector<FrameSet> more) {
    for (FrameSet& s : more) sets.push_back(std::move(s));
  };
  for (uint64_t n = 0; n < 10; ++n) {
    for (uint32_t cam : {1u, 2u}) {
      if (cam == 2 && n == 4) continue;  // lost frame
      const auto packets = EncodeCameraFrame(testing::FrameOfBlobs(cam, n, 60));  // two chunks each
      ASSERT_EQ(packets.size(), 2u);
      Datagram first;
      for (const auto& p : packets) {
        const Datagram d = nodes.Seal(cam, p);
        if (first.bytes.empty()) first = d;
        ingest.Add(d, &writer);
        EXPECT_EQ(ingest.last_outcome(), IngestOutcome::kAccepted);
      }
      if (n == 2 && cam == 1) {
        ingest.Add(first, &writer);  // the same datagram again: a replay
        EXPECT_EQ(ingest.last_outcome(), IngestOutcome::kUnauthentic);
        ingest.Add(nodes.Seal(cam, packets[0]), &writer);  // the same chunk sent again: a duplicate
      }
    }
    const std::vector<uint8_t> junk{0xde, 0xad, 0xbe, 0xef};
    ingest.Add(Nodes::Received(junk), &writer);  // plain: unauthenticated
    EXPECT_EQ(ingest.last_outcome(), IngestOutcome::kUnauthentic);
    ingest.Add(nodes.Seal(1, junk), &writer);  // authentic, but not a packet: malformed
    EXPECT_EQ(ingest.last_outcome(), IngestOutcome::kMalformed);
    const wire::WireKey forged{};  // frames for node 2 under a key the attacker made up
    ingest.Add(nodes.Seal(2, EncodeCameraFrame(testing::FrameOfBlobs(2, n, 3))[0], &forged), &writer);
    EXPECT_EQ(ingest.last_outcome(), IngestOutcome::kUnauthentic);
    ingest.Add(nodes.Seal(9, EncodeCameraFrame(testing::FrameOfBlobs(9, n, 1))[0]), &writer);  // not in the calibration
    take(ingest.Collect(RealtimeNowNs()));
  }
  take(ingest.Flush());
  writer.Finish();

  ASSERT_EQ(sets.size(), 10u);
  for (size_t i = 0; i < sets.size(); ++i) {
    const FrameSet& s = sets[i];
    EXPECT_EQ(s.frame_number, i);
    EXPECT_EQ(s.cameras.size(), s.frame_number == 4 ? 1u : 2u) << "frame " << s.frame_number;
    for (const CameraFrame& f : s.cameras) EXPECT_EQ(f.blobs.size(), 60u);
  }
  const IngestStats& st = ingest.stats();
  EXPECT_EQ(st.nodes.at(1).frames, 10u);
  EXPECT_EQ(st.nodes.at(2).frames, 9u);
  EXPECT_EQ(st.nodes.at(2).dropped_frames, 1u);
  EXPECT_EQ(st.nodes.at(1).duplicate_chunks, 1u);
  EXPECT_EQ(st.malformed, 10u);
  EXPECT_EQ(st.unknown_nodes.at(9), 10u);
  EXPECT_EQ(st.unknown_nodes.size(), 1u);
  // Every forged, plain and replayed datagram refused and counted, none in the frame sets (the
  // forged frames carried 3 markers: every set above has 60 per camera).
  EXPECT_EQ(st.unauthentic, 21u);
  const WireAuth& wire_auth = ingest.auth();
  EXPECT_EQ(wire_auth.Rejected(WireRejection::kUnauthenticated), 10u);
  EXPECT_EQ(wire_auth.Rejected(WireRejection::kBadTag), 10u);
  EXPECT_EQ(wire_auth.Rejected(WireRejection::kReplayed), 1u);
  EXPECT_EQ(wire_auth.Counts(2)->by_kind.at(WireRejection::kBadTag), 10u);
  EXPECT_EQ(wire_auth.Counts(1)->by_kind.at(WireRejection::kReplayed), 1u);
  EXPECT_EQ(wire_auth.StatusJson()["nodes"]["2"]["rejected"], 10);

  // The raw log holds the good packets as received (the duplicate chunk with them, as sent) and
  // nothing refused: it replays into the same ten sets.
  SessionReader reader;
  reader.Open((dir / "session").string());
  FrameSet set;
  int replayed = 0;
  while (reader.Next(&set)) {
    EXPECT_EQ(set.cameras.size(), set.frame_number == 4 ? 1u : 2u) << "frame " << set.frame_number;
    for (const CameraFrame& f : set.cameras) EXPECT_EQ(f.blobs.size(), 60u);
    ++replayed;
  }
  EXPECT_EQ(replayed, 10);
  EXPECT_EQ(reader.stats().duplicate_chunks, 1u);
}

TEST(FrameIngest, RefusesAWireWithoutKeysAndBadAssembly) {
  FrameSetAssemblerOptions assembly;
  WireAuthOptions auth;
  EXPECT_THROW(FrameIngest({1}, assembly, auth), std::invalid_argument);  // neither keys nor the insecure wire
  auth.keys_dir = "/nonexistent/keys";
  EXPECT_THROW(FrameIngest({1}, assembly, auth), std::runtime_error);
  auth.keys_dir.clear();
  auth.insecure_dev = true;
  EXPECT_NO_THROW(FrameIngest({1}, assembly, auth));
  assembly.deadline_ns = 0;
  EXPECT_THROW(FrameIngest({1}, assembly, auth), std::invalid_argument);
}

}  // namespace
}  // namespace mocap

// A live recording over loopback UDP: chunked frames from two nodes sealed under their keys, a
// duplicate chunk, junk (plain and sealed), forged frames, a replayed datagram, a node not in
// the calibration and a lost frame; the session log keeps every good packet as received.
#include "ingest/recorder.h"

#include <filesystem>
#include <map>
#include <thread>

#include <gtest/gtest.h>

#include "ingest/camera_frame_testing.h"
#include "ingest/frame_codec.h"
#include "wire/datagram_envelope.h"
#include "util/temporary_directory_testing.h"
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
  std::vector<uint8_t> Seal(uint32_t node, const std::vector<uint8_t>& payload, const wire::WireKey* key = nullptr) {
    counter_ = wire::NextCounter(counter_, RealtimeNowNs());
    return wire::SealEnvelope({wire::Direction::kToHub, 1, node, counter_}, key ? *key : keys_.at(node),
                              payload.data(), payload.size());
  }

 private:
  std::map<uint32_t, wire::WireKey> keys_;
  uint64_t counter_ = 0;
};

TEST(Recorder, AssemblesLogsAndCountsOverLoopback) {
  const testing::TemporaryDirectory temp("recorder_test");
  const fs::path& dir = temp.path();
  Nodes nodes(dir / "keys");
  RecorderOptions o;
  o.auth.keys_dir = (dir / "keys").string();
  o.listen = "127.0.0.1:0";
  o.cameras = {1, 2};
  o.rate_hz = 100;
  o.idle_timeout_s = 0.3;
  o.assembly.deadline_ns = 50'000'000;
  Recorder recorder(o);
  recorder.Bind();
  const uint16_t port = recorder.port();
  ASSERT_NE(port, 0);

  SessionInfo info;
  info.rate_hz = 100;
  info.camera_ids = {1, 2};
  SessionWriter writer;
  writer.Create((dir / "session").string(), info);

  std::thread sender([port, &nodes] {
    UdpSocket out;
    out.Bind(ParseHostPort("127.0.0.1:0"));
    const HostPort hub{"127.0.0.1", port};
    for (uint64_t n = 0; n < 10; ++n) {
      for (uint32_t cam : {1u, 2u}) {
        if (cam == 2 && n == 4) continue;  // lost frame
        auto packets = EncodeCameraFrame(testing::FrameOfBlobs(cam, n, 60));  // two chunks each
        std::vector<uint8_t> first;
        for (const auto& p : packets) {
          const std::vector<uint8_t> d = nodes.Seal(cam, p);
          if (first.empty()) first = d;
          out.SendTo(hub, d);
        }
        if (n == 2 && cam == 1) {
          out.SendTo(hub, first);                      // the same datagram again: a replay
          out.SendTo(hub, nodes.Seal(cam, packets[0]));  // the same chunk sent again: a duplicate
        }
      }
      const std::vector<uint8_t> junk{0xde, 0xad, 0xbe, 0xef};
      out.SendTo(hub, junk);                 // plain: unauthenticated
      out.SendTo(hub, nodes.Seal(1, junk));  // authentic, but not a packet: malformed
      const wire::WireKey forged{};          // frames for node 2 under a key the attacker made up
      out.SendTo(hub, nodes.Seal(2, EncodeCameraFrame(testing::FrameOfBlobs(2, n, 3))[0], &forged));
      out.SendTo(hub, nodes.Seal(9, EncodeCameraFrame(testing::FrameOfBlobs(9, n, 1))[0]));  // not in the calibration
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
  });
  std::vector<FrameSet> sets;
  recorder.Run(&writer, [&](const FrameSet& s) { sets.push_back(s); }, nullptr);
  sender.join();
  writer.Finish();

  ASSERT_EQ(sets.size(), 10u);
  for (const FrameSet& s : sets) {
    EXPECT_EQ(s.cameras.size(), s.frame_number == 4 ? 1u : 2u) << "frame " << s.frame_number;
    for (const CameraFrame& f : s.cameras) EXPECT_EQ(f.blobs.size(), 60u);
  }
  const IngestStats& st = recorder.stats();
  EXPECT_EQ(st.nodes.at(1).frames, 10u);
  EXPECT_EQ(st.nodes.at(2).frames, 9u);
  EXPECT_EQ(st.nodes.at(2).dropped_frames, 1u);
  EXPECT_EQ(st.nodes.at(1).duplicate_chunks, 1u);
  EXPECT_EQ(st.malformed, 10u);
  EXPECT_EQ(st.unknown_nodes.at(9), 10u);
  EXPECT_NE(st.Report().find("unknown node 9"), std::string::npos);
  // Every forged, plain and replayed datagram refused and counted, none in the frame sets (the
  // forged frames carried 3 markers: every set above has 60 per camera).
  EXPECT_EQ(st.unauthentic, 21u);
  const WireAuth& auth = recorder.auth();
  EXPECT_EQ(auth.Rejected(WireRejection::kUnauthenticated), 10u);
  EXPECT_EQ(auth.Rejected(WireRejection::kBadTag), 10u);
  EXPECT_EQ(auth.Rejected(WireRejection::kReplayed), 1u);
  EXPECT_EQ(auth.Counts(2)->by_kind.at(WireRejection::kBadTag), 10u);
  EXPECT_EQ(auth.Counts(1)->by_kind.at(WireRejection::kReplayed), 1u);
  EXPECT_EQ(auth.StatusJson()["nodes"]["2"]["rejected"], 10);

  SessionReader reader;
  reader.Open((dir / "session").string());
  FrameSet set;
  int replayed = 0;
  while (reader.Next(&set)) ++replayed;
  EXPECT_EQ(replayed, 10);
  EXPECT_EQ(reader.stats().duplicate_chunks, 1u);
}

TEST(Recorder, RefusesBadOptions) {
  RecorderOptions o;
  EXPECT_THROW(Recorder{o}, std::invalid_argument);
  o.cameras = {1};
  EXPECT_THROW(Recorder{o}, std::invalid_argument);  // neither keys nor the insecure wire
  o.auth.keys_dir = "/nonexistent/keys";
  EXPECT_THROW(Recorder{o}, std::runtime_error);
  o.auth.keys_dir.clear();
  o.auth.insecure_dev = true;
  o.cameras = {1};
  o.listen = "nonsense";
  EXPECT_THROW(Recorder{o}, std::invalid_argument);
  o.listen = "127.0.0.1:99999";
  EXPECT_THROW(Recorder{o}, std::invalid_argument);
}

}  // namespace
}  // namespace mocap

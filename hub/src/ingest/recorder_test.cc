// A live recording over loopback UDP: chunked frames from two nodes, a duplicate chunk, junk,
// an unknown node and a lost frame; the session log keeps every good datagram as received.
#include "ingest/recorder.h"

#include <filesystem>
#include <thread>

#include <gtest/gtest.h>

#include "ingest/frame_codec.h"

namespace mocap {
namespace {
namespace fs = std::filesystem;

CameraFrame Frame(uint32_t cam, uint64_t number, int blobs) {
  CameraFrame f;
  f.camera_id = cam;
  f.frame_number = number;
  f.width = 1280;
  f.height = 800;
  for (int i = 0; i < blobs; ++i) {
    Blob b;
    b.pixel = Eigen::Vector2d(5.0 + i, 6.0 + number);
    b.area = 9;
    b.peak = 200;
    b.mean = 120;
    f.blobs.push_back(b);
  }
  return f;
}

TEST(Recorder, AssemblesLogsAndCountsOverLoopback) {
  RecorderOptions o;
  o.listen = "127.0.0.1:0";
  o.cameras = {1, 2};
  o.rate_hz = 100;
  o.idle_timeout_s = 0.3;
  o.assembly.deadline_ns = 50'000'000;
  Recorder recorder(o);
  recorder.Bind();
  const uint16_t port = recorder.port();
  ASSERT_NE(port, 0);

  const fs::path dir = fs::temp_directory_path() / ("mocap_recorder_test_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  SessionInfo info;
  info.rate_hz = 100;
  info.camera_ids = {1, 2};
  SessionWriter writer;
  writer.Create(dir.string(), info);

  std::thread sender([port] {
    UdpSocket out;
    out.Bind(ParseHostPort("127.0.0.1:0"));
    const HostPort hub{"127.0.0.1", port};
    for (uint64_t n = 0; n < 10; ++n) {
      for (uint32_t cam : {1u, 2u}) {
        if (cam == 2 && n == 4) continue;  // lost frame
        auto datagrams = EncodeCameraFrame(Frame(cam, n, 60));  // two chunks each
        for (const auto& d : datagrams) out.SendTo(hub, d);
        if (n == 2 && cam == 1) out.SendTo(hub, datagrams[0]);  // duplicated chunk
      }
      out.SendTo(hub, std::vector<uint8_t>{0xde, 0xad, 0xbe, 0xef});
      out.SendTo(hub, EncodeCameraFrame(Frame(9, n, 1))[0]);  // unknown node
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

  SessionReader reader;
  reader.Open(dir.string());
  FrameSet set;
  int replayed = 0;
  while (reader.Next(&set)) ++replayed;
  EXPECT_EQ(replayed, 10);
  EXPECT_EQ(reader.stats().duplicate_chunks, 1u);
  fs::remove_all(dir);
}

TEST(Recorder, RefusesBadOptions) {
  RecorderOptions o;
  EXPECT_THROW(Recorder{o}, std::invalid_argument);
  o.cameras = {1};
  o.listen = "nonsense";
  EXPECT_THROW(Recorder{o}, std::invalid_argument);
  o.listen = "127.0.0.1:99999";
  EXPECT_THROW(Recorder{o}, std::invalid_argument);
}

}  // namespace
}  // namespace mocap

// `record` is serve's loop run headless: a HubService without sessions directory, API or
// streams, with one DirectCapture, on loopback. Frames of four cameras and one frame of a node
// numbering on another clock arrive before the loop runs; the loop counts exactly the frame
// sets asked for, ends by itself, and answers the off-clock node with the session's grid as
// serve does (record's own loop used to ignore such a node).
#include <atomic>
#include <chrono>
#include <filesystem>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "ingest/camera_frame_testing.h"
#include "ingest/frame_codec.h"
#include "io/calibration_json.h"
#include "service/hub_service.h"
#include "simcore/test_scenes.h"
#include "util/temporary_directory_testing.h"
#include "wire/packet.h"

namespace mocap::service {
namespace {
namespace fs = std::filesystem;

TEST(RecordLoop, CountsExactlyItsFrameSetsAndSendsAnOffClockNodeTheGrid) {
  const mocap::testing::TemporaryDirectory temp("record_loop_test");
  const Rig rig = mocap::testing::RingRig(4, 1);
  SaveRigJson(rig, (temp.path() / "calibration.json").string());
  ServeOptions options;
  options.listen = "127.0.0.1:0";
  options.calibration = (temp.path() / "calibration.json").string();
  options.sessions_dir.clear();  // record's hub
  options.auth.insecure_dev = true;
  options.calibration_monitor = false;
  options.rate_hz = 100;
  options.epoch_ns = RealtimeNowNs();
  options.disk.start_free_mb = 1.0;
  options.disk.warn_free_mb = 1.0;
  options.disk.stop_free_mb = 0.5;
  HubService hub(options);
  hub.Bind();

  DirectCapture capture;
  capture.dir = (temp.path() / "rec").string();
  capture.max_frame_sets = 4;
  std::vector<uint64_t> told;
  capture.on_frame = [&told](const FrameSet& set, const pipeline::LiveFrame&) { told.push_back(set.frame_number); };
  hub.StartDirectCapture(capture);

  UdpSocket node;
  node.Bind(ParseHostPort("127.0.0.1:0"));
  const HostPort to{"127.0.0.1", hub.port()};
  for (uint64_t n = 0; n < 8; ++n)
    for (const Camera& camera : rig.cameras)
      for (const auto& packet : EncodeCameraFrame(mocap::testing::FrameOfBlobs(camera.id, n, 3)))
        node.SendTo(to, packet);
  const uint32_t off_clock = rig.cameras[0].id;
  CameraFrame ahead = mocap::testing::FrameOfBlobs(off_clock, 0, 3);
  ahead.frame_number = 100000;  // 1000 s ahead of the session's clock
  for (const auto& packet : EncodeCameraFrame(ahead)) node.SendTo(to, packet);

  // The loop ends by itself; the stop flag only bounds a hang.
  std::atomic<bool> stop{false}, returned{false};
  std::thread guard([&] {
    for (int i = 0; i < 600 && !returned; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(100));
    if (!returned) stop = true;
  });
  hub.Run(stop);
  returned = true;
  guard.join();
  EXPECT_FALSE(stop) << "the loop did not end at its frame limit";

  EXPECT_EQ(told, (std::vector<uint64_t>{0, 1, 2, 3}));
  const nlohmann::json& summary = hub.last_capture();
  EXPECT_EQ(summary["state"], "complete");
  EXPECT_EQ(summary["frame_sets"], 4);
  const SessionInfo info = LoadSessionInfo(capture.dir);
  EXPECT_EQ(info.frame_sets, 4u);
  EXPECT_EQ(info.source, "record");
  EXPECT_EQ(hub.ingest().stats().nodes.at(off_clock).off_clock_frames, 1u);

  // serve's answer to a node on another clock: a Start with the session's epoch and rate.
  bool grid = false;
  for (int i = 0; i < 20 && !grid; ++i) {
    Datagram d;
    if (!node.Receive(&d, 100)) continue;
    const wire::DecodeResult decoded = wire::Decode(d.bytes.data(), d.bytes.size());
    if (!decoded.ok || !decoded.packet.has_control() || !decoded.packet.control().has_start()) continue;
    EXPECT_EQ(decoded.packet.control().node_id(), off_clock);
    EXPECT_EQ(decoded.packet.control().start().epoch_ns(), options.epoch_ns);
    EXPECT_EQ(decoded.packet.control().start().rate_millihz(), 100000u);
    grid = true;
  }
  EXPECT_TRUE(grid) << "the off-clock node was not sent the session's grid";
}

}  // namespace
}  // namespace mocap::service

// The live hub's JSON views, without a loop: a request's outcome, a node with its reception and
// mask, the calibration's cameras and the console's blobs as the API answers them.
#include "service/hub_json.h"

#include <gtest/gtest.h>

namespace mocap::service {
namespace {

constexpr uint64_t kSecond = 1'000'000'000;

Rig TwoCameras() {
  Rig rig;
  for (uint32_t id : {4u, 5u}) {
    Camera c;
    c.id = id;
    c.intrinsics.width = 1280;
    c.intrinsics.height = 800;
    c.intrinsics.fx = c.intrinsics.fy = 1000.0;
    c.intrinsics.cx = 640.0;
    c.intrinsics.cy = 400.0;
    c.translation = Eigen::Vector3d(0.0, 0.0, 100.0 * id);  // centre at (0, 0, -100 id)
    rig.cameras.push_back(c);
  }
  return rig;
}

CameraMask Mask(uint32_t camera, std::vector<MaskRect> regions) {
  CameraMask mask;
  mask.camera_id = camera;
  mask.regions = std::move(regions);
  return mask;
}

TEST(HubJson, RequestCarriesItsOutcomeAndDuration) {
  RequestResult r;
  r.node_id = 4;
  r.outcome = RequestOutcome::kRejected;
  r.reason = "out of range";
  r.datagrams = 2;
  r.retransmissions = 1;
  r.submitted_ns = 10 * kSecond;
  r.finished_ns = 10 * kSecond + 3'500'000;
  const nlohmann::json j = RequestJson(r);
  EXPECT_EQ(j["node"], 4);
  EXPECT_EQ(j["outcome"], "rejected");
  EXPECT_EQ(j["reason"], "out of range");
  EXPECT_EQ(j["datagrams"], 2);
  EXPECT_EQ(j["retransmissions"], 1);
  EXPECT_DOUBLE_EQ(j["ms"].get<double>(), 3.5);
}

TEST(HubJson, NodeWithItsReceptionMaskAndLastSeen) {
  NodeEntry n;
  n.id = 4;
  n.address = "10.0.0.4:5000";
  n.state = NodeState::kRunning;
  n.last_seen_ns = 10 * kSecond;
  n.has_temperature = true;
  n.temperature_c = 51.5;
  IngestStats stats;
  stats.nodes[4].off_clock_frames = 7;
  const nlohmann::json j = NodeJson(n, stats, {Mask(5, {}), Mask(4, {{1, 2, 3, 4}})}, 12 * kSecond);
  EXPECT_EQ(j["id"], 4);
  EXPECT_EQ(j["address"], "10.0.0.4:5000");
  EXPECT_EQ(j["state"], "running");
  EXPECT_EQ(j["off_clock_frames"], 7);
  EXPECT_DOUBLE_EQ(j["last_seen_s"].get<double>(), 2.0);
  EXPECT_DOUBLE_EQ(j["temperature_c"].get<double>(), 51.5);
  EXPECT_TRUE(j["masked"].get<bool>());
  EXPECT_TRUE(j["sync"].contains("edge_jitter_ns"));
}

TEST(HubJson, LostNodeOutsideTheCalibrationHasZeroReceptionAndNoMask) {
  NodeEntry n;
  n.id = 9;
  n.lost = true;
  n.state = NodeState::kRunning;
  const nlohmann::json j = NodeJson(n, IngestStats(), {Mask(9, {})}, 12 * kSecond);
  EXPECT_EQ(j["state"], "lost");
  EXPECT_EQ(j["off_clock_frames"], 0);
  EXPECT_DOUBLE_EQ(j["last_seen_s"].get<double>(), 0.0);  // never seen
  EXPECT_TRUE(j["temperature_c"].is_null());
  EXPECT_FALSE(j["masked"].get<bool>());  // a mask without regions masks nothing
}

TEST(HubJson, CamerasWithTheirGeometry) {
  const nlohmann::json j = CamerasJson(TwoCameras());
  ASSERT_EQ(j.size(), 2u);
  EXPECT_EQ(j[1]["id"], 5);
  EXPECT_EQ(j[1]["width"], 1280);
  EXPECT_DOUBLE_EQ(j[1]["fx"].get<double>(), 1000.0);
  EXPECT_EQ(j[1]["distortion"].size(), 5u);
  EXPECT_EQ(j[1]["rotation"].size(), 3u);
  EXPECT_DOUBLE_EQ(j[1]["translation"][2].get<double>(), 500.0);
  EXPECT_DOUBLE_EQ(j[1]["centre"][2].get<double>(), -500.0);
}

TEST(HubJson, BlobsPerCameraWithMasks) {
  FrameSet set;
  set.frame_number = 42;
  CameraFrame frame;
  frame.camera_id = 5;
  Blob b;
  b.pixel = Eigen::Vector2d(10.5, 20.0);
  b.area = 9;
  frame.blobs.push_back(b);
  set.cameras.push_back(frame);
  const nlohmann::json j = BlobsJson(TwoCameras(), BlobsSnapshot{set, {Mask(4, {{1, 2, 3, 4}})}});
  EXPECT_EQ(j["frame"], 42);
  ASSERT_EQ(j["cameras"].size(), 2u);
  EXPECT_FALSE(j["cameras"][0]["seen"].get<bool>());
  EXPECT_EQ(j["cameras"][0]["mask"], nlohmann::json::parse("[[1, 2, 3, 4]]"));
  EXPECT_TRUE(j["cameras"][1]["seen"].get<bool>());
  EXPECT_EQ(j["cameras"][1]["blobs"], nlohmann::json::parse("[[10.5, 20.0, 9]]"));
  EXPECT_TRUE(j["cameras"][1]["mask"].empty());
}

TEST(HubJson, NoFrameSetInTime) {
  const nlohmann::json j = BlobsJson(TwoCameras(), BlobsSnapshot{std::nullopt, {}});
  EXPECT_TRUE(j["frame"].is_null());
  EXPECT_FALSE(j["cameras"][0]["seen"].get<bool>());
  EXPECT_EQ(j["cameras"][0]["width"], 1280);
}

}  // namespace
}  // namespace mocap::service

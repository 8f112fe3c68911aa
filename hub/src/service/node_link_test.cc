// The control plane across the hub/firmware boundary, without sockets: an automatic mask
// computed from the firmware detector's own blobs travels as hub Control datagrams through a
// lossy link into the firmware's control handler, the firmware's ControlAcks come back into
// ControlRequests (with retransmission), and the detector then no longer sees the reflections
// while the markers stay.
#include <cmath>
#include <cstring>
#include <random>
#include <set>

#include <gtest/gtest.h>

extern "C" {
#include "node/control.h"
}
#include "detect/detect.h"
#include "service/auto_mask.h"
#include "service/control_requests.h"
#include "wire/packet.h"
#include "wire/wire.h"

namespace mocap::service {
namespace {

constexpr uint32_t kNode = 6, kW = 640, kH = 400;
constexpr uint64_t kMs = 1'000'000;

// The parts of mocap-node under test: its control handler, its detector, and what node.c does
// with a command (apply, then answer).
class Node {
 public:
  Node() : control_(mn_control_new(kNode)) {
    mn_detect_config cfg;
    mn_detect_config_default(&cfg);
    cfg.threshold = 60;
    detector_ = mn_detector_new(&cfg, kW, kH);
  }
  ~Node() {
    mn_detector_free(detector_);
    mn_control_free(control_);
  }
  Node(const Node&) = delete;
  Node& operator=(const Node&) = delete;

  // Takes one hub datagram; returns the ack datagram (empty when the node does not answer).
  std::vector<uint8_t> Receive(const std::vector<uint8_t>& datagram) {
    mn_command cmd;
    const char* why = nullptr;
    mn_control_result r = mn_control_handle(control_, datagram.data(), datagram.size(), false, &cmd, &why);
    if (r == MN_CONTROL_ACCEPTED) Apply(cmd);
    if (!cmd.acknowledge) return {};
    static mocap_v1_Packet ack;
    mn_wire_control_ack(kNode, cmd.sequence,
                        r == MN_CONTROL_ACCEPTED  ? mocap_v1_ControlResult_CONTROL_RESULT_APPLIED
                        : r == MN_CONTROL_IGNORED ? mocap_v1_ControlResult_CONTROL_RESULT_IGNORED
                                                  : mocap_v1_ControlResult_CONTROL_RESULT_REJECTED,
                        r == MN_CONTROL_ACCEPTED ? nullptr : why, &ack);
    std::vector<uint8_t> out(MN_WIRE_MAX_DATAGRAM);
    size_t size = 0;
    const char* reason = nullptr;
    EXPECT_EQ(mn_wire_encode(&ack, out.data(), out.size(), &size, &reason), 0) << reason;
    out.resize(size);
    return out;
  }

  CameraFrame Detect(const std::vector<uint8_t>& pixels, uint64_t frame_number) {
    std::vector<mn_blob> blobs(256);
    size_t n = 0;
    EXPECT_EQ(mn_detector_run(detector_, pixels.data(), kW, kH, kW, blobs.data(), blobs.size(), &n), 0);
    CameraFrame frame;
    frame.camera_id = kNode;
    frame.frame_number = frame_number;
    frame.width = kW;
    frame.height = kH;
    for (size_t i = 0; i < n; ++i) {
      Blob b;
      b.pixel = {blobs[i].x, blobs[i].y};
      b.area = blobs[i].area;
      b.peak = blobs[i].peak;
      b.mean = blobs[i].mean;
      frame.blobs.push_back(b);
    }
    return frame;
  }

  int masks_applied = 0;

 private:
  void Apply(const mn_command& cmd) {
    switch (cmd.kind) {
      case MN_CMD_MASK_BITS:
        ASSERT_EQ(mn_detector_set_mask_bits(detector_, cmd.u.bits.cell_px, cmd.u.bits.cells_x, cmd.u.bits.cells_y,
                                            cmd.u.bits.bits), 0);
        ++masks_applied;
        break;
      case MN_CMD_MASK_RECTS: {
        std::vector<mn_rect> rects;
        for (size_t i = 0; i < cmd.u.rects.n; ++i)
          rects.push_back({cmd.u.rects.rects[i].x, cmd.u.rects.rects[i].y, cmd.u.rects.rects[i].w,
                           cmd.u.rects.rects[i].h});
        ASSERT_EQ(mn_detector_set_mask_rects(detector_, rects.data(), rects.size()), 0);
        ++masks_applied;
        break;
      }
      case MN_CMD_MASK_CLEAR:
        mn_detector_clear_mask(detector_);
        break;
      default:
        break;
    }
  }
  mn_control* control_;
  mn_detector* detector_;
};

struct Scene {
  std::vector<std::pair<double, double>> reflections;
  // Frame k: the reflections, and markers walking across the view.
  std::vector<uint8_t> Render(uint64_t k) const {
    std::vector<double> v(size_t{kW} * kH, 10.0);
    auto spot = [&v](double cx, double cy, double sigma, double amp) {
      for (int y = std::max(0, int(cy) - 8); y < std::min(int(kH), int(cy) + 9); ++y)
        for (int x = std::max(0, int(cx) - 8); x < std::min(int(kW), int(cx) + 9); ++x)
          v[size_t(y) * kW + x] += amp * std::exp(-((x - cx) * (x - cx) + (y - cy) * (y - cy)) / (2 * sigma * sigma));
    };
    for (const auto& [x, y] : reflections) spot(x, y, 1.4, 180.0);
    for (int m = 0; m < 4; ++m) spot(40.0 + 5.0 * double(k) + 60.0 * m, 60.0 + 90.0 * m, 1.2, 200.0);
    std::vector<uint8_t> px(v.size());
    for (size_t i = 0; i < v.size(); ++i) px[i] = static_cast<uint8_t>(std::min(255.0, v[i]));
    return px;
  }
};

// Hub <-> node over a link that loses the datagrams (hub to node) and acks (node to hub) whose
// sequences are listed, once each.
struct Link {
  std::set<uint32_t> lose_datagram, lose_ack;
  int delivered = 0;
  void Send(const std::vector<v1::Packet>& packets, Node* node, ControlRequests* requests, uint64_t now,
            std::vector<RequestResult>* finished) {
    for (const v1::Packet& p : packets) {
      const uint32_t seq = p.control().sequence();
      if (lose_datagram.erase(seq)) continue;
      ++delivered;
      const std::vector<uint8_t> ack = node->Receive(wire::Encode(p));
      if (ack.empty() || lose_ack.erase(seq)) continue;
      const wire::DecodeResult decoded = wire::Decode(ack.data(), ack.size());
      ASSERT_TRUE(decoded.ok) << decoded.reason;
      if (auto done = requests->OnAck(decoded.packet.control_ack(), now)) finished->push_back(*done);
    }
  }
};

size_t BlobsNear(const CameraFrame& frame, double x, double y) {
  size_t n = 0;
  for (const Blob& b : frame.blobs) n += std::hypot(b.pixel.x() - x, b.pixel.y() - y) < 3.0;
  return n;
}

void MaskReflections(const Scene& scene, const std::set<uint32_t>& lose_datagram_index,
                     const std::set<uint32_t>& lose_ack_index, bool expect_image) {
  Node node;
  std::vector<CameraFrame> empty_volume;
  for (uint64_t k = 0; k < 30; ++k) empty_volume.push_back(node.Detect(scene.Render(k), k));
  ASSERT_EQ(empty_volume[0].blobs.size(), scene.reflections.size() + 4);

  const CameraMask mask = ComputeAutoMask(empty_volume, AutoMaskOptions{});
  EXPECT_EQ(mask.blobs.size(), scene.reflections.size());
  const std::vector<v1::Control> commands = MaskCommands(mask);
  EXPECT_EQ(commands.size() > 1, expect_image);

  ControlRequestsOptions options;
  options.first_sequence = 0xfffffff0u;  // across the wrap, as a clock-seeded hub may be
  ControlRequests requests(options);
  const SubmitResult submitted = requests.Submit(kNode, commands, 0);
  ASSERT_TRUE(submitted.ok);
  Link link;
  for (uint32_t i : lose_datagram_index) link.lose_datagram.insert(submitted.send[i].control().sequence());
  for (uint32_t i : lose_ack_index) link.lose_ack.insert(submitted.send[i].control().sequence());
  std::vector<RequestResult> finished;
  link.Send(submitted.send, &node, &requests, kMs, &finished);
  if (!lose_datagram_index.empty() || !lose_ack_index.empty()) {
    EXPECT_TRUE(finished.empty());
    const auto tick = requests.Tick(options.retransmit_after_ns);
    EXPECT_EQ(tick.resend.size(), lose_datagram_index.size() + lose_ack_index.size());
    link.Send(tick.resend, &node, &requests, options.retransmit_after_ns + kMs, &finished);
  }
  ASSERT_EQ(finished.size(), 1u);
  EXPECT_EQ(finished[0].outcome, RequestOutcome::kApplied) << finished[0].reason;
  EXPECT_EQ(node.masks_applied, 1);
  EXPECT_EQ(requests.pending(), 0u);

  // The volume in use: every marker is still found, no reflection is.
  for (uint64_t k = 40; k < 45; ++k) {
    const CameraFrame frame = node.Detect(scene.Render(k), k);
    EXPECT_EQ(frame.blobs.size(), 4u) << "frame " << k;
    for (const auto& [x, y] : scene.reflections) EXPECT_EQ(BlobsNear(frame, x, y), 0u);
  }
}

TEST(NodeLink, FewReflectionsMaskedByRectangles) {
  Scene scene;
  scene.reflections = {{500.0, 30.0}, {600.5, 350.25}, {20.0, 380.0}};
  MaskReflections(scene, {}, {}, false);
}

TEST(NodeLink, ManyReflectionsMaskedByTheCellImageOverALossyLink) {
  Scene scene;
  for (int i = 0; i < 24; ++i) scene.reflections.push_back({30.0 + 25.0 * i, 330.0 + 10.0 * (i % 3)});
  // Chunk 3's ack is lost on the way back, chunk 7 on the way there: both are sent again, 3
  // first; the node ignores 3 (stored already, not a new image) and stores 7, completing it.
  MaskReflections(scene, {7}, {3}, true);
}

TEST(NodeLink, RejectionCarriesTheNodesReason) {
  Node node;
  ControlRequests requests;
  v1::Control threshold;
  threshold.mutable_set_threshold()->set_value(300);  // fine on the wire, not for a Y8 node
  const SubmitResult submitted = requests.Submit(kNode, {threshold}, 0);
  std::vector<RequestResult> finished;
  Link link;
  link.Send(submitted.send, &node, &requests, kMs, &finished);
  ASSERT_EQ(finished.size(), 1u);
  EXPECT_EQ(finished[0].outcome, RequestOutcome::kRejected);
  EXPECT_EQ(finished[0].reason, "control: threshold outside 1..255");
}

}  // namespace
}  // namespace mocap::service

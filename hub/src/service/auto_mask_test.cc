// Automatic masks: persistent blobs found among moving markers and flicker, margins that grow
// with blob size, the node's two representations within its limits, and the mask file.
#include "service/auto_mask.h"

#include <cmath>
#include <random>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "wire/packet.h"

namespace mocap::service {
namespace {

struct Spot {
  double x, y;
  uint32_t area;
  double presence;  // chance of being seen in a frame
};

// Frames of an empty volume: static spots with centroid jitter, plus blobs that wander (a
// person walking through the view) and one-frame flicker at random places.
std::vector<CameraFrame> Frames(const std::vector<Spot>& spots, size_t n, uint32_t seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> jitter(0.0, 0.15);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<CameraFrame> frames(n);
  for (size_t f = 0; f < n; ++f) {
    CameraFrame& frame = frames[f];
    frame.camera_id = 4;
    frame.frame_number = 1000 + f;
    frame.width = 1280;
    frame.height = 800;
    for (const Spot& s : spots) {
      if (u(rng) >= s.presence) continue;
      Blob b;
      b.pixel = {s.x + jitter(rng), s.y + jitter(rng)};
      b.area = s.area;
      frame.blobs.push_back(b);
    }
    for (int k = 0; k < 3; ++k) {  // wanderers move 8 px per frame
      Blob b;
      b.pixel = {100.0 + 8.0 * static_cast<double>(f) + 150.0 * k, 400.0 + 40.0 * k};
      b.area = 30;
      frame.blobs.push_back(b);
    }
    Blob flicker;
    flicker.pixel = {u(rng) * 1279.0, u(rng) * 799.0};
    flicker.area = 5;
    frame.blobs.push_back(flicker);
  }
  return frames;
}

bool Covers(const std::vector<MaskRect>& regions, double x, double y) {
  for (const MaskRect& r : regions)
    if (x >= r.x - 0.5 && x <= r.x + r.width - 0.5 && y >= r.y - 0.5 && y <= r.y + r.height - 0.5) return true;
  return false;
}

TEST(AutoMask, FindsPersistentBlobsOnly) {
  const std::vector<Spot> spots = {
      {200.0, 100.0, 12, 1.0},   // a screw head
      {900.5, 620.25, 300, 0.9}, // a lamp: large, sometimes lost in saturation
      {640.0, 50.0, 20, 0.5},    // flickers half the time: below min_presence
  };
  const CameraMask mask = ComputeAutoMask(Frames(spots, 100, 1), AutoMaskOptions{});
  EXPECT_EQ(mask.camera_id, 4u);
  EXPECT_EQ(mask.width, 1280u);
  EXPECT_EQ(mask.frames, 100u);
  ASSERT_EQ(mask.blobs.size(), 2u);
  EXPECT_NEAR(mask.blobs[0].x, 200.0, 0.1);
  EXPECT_NEAR(mask.blobs[0].y, 100.0, 0.1);
  EXPECT_NEAR(mask.blobs[0].radius_px, std::sqrt(12 / M_PI), 1e-9);
  EXPECT_GE(mask.blobs[1].presence, 0.8);
  EXPECT_NEAR(mask.blobs[1].x, 900.5, 0.1);
  ASSERT_EQ(mask.regions.size(), 2u);
  // Each spot's disc plus its margin is masked, and the big lamp gets the bigger margin.
  for (const Spot& s : {spots[0], spots[1]}) {
    const double reach = 2.0 * std::sqrt(s.area / M_PI) + 2.0;
    for (double a = 0; a < 2 * M_PI; a += 0.3)
      EXPECT_TRUE(Covers(mask.regions, s.x + reach * std::cos(a), s.y + reach * std::sin(a)));
  }
  EXPECT_LT(mask.regions[0].width, mask.regions[1].width);
  EXPECT_FALSE(Covers(mask.regions, 640.0, 50.0));
  EXPECT_LT(mask.regions[0].width, 20u);  // tight around the screw head: no wanderer joined it
}

TEST(AutoMask, ACreepingMarkerIsNoReflection) {
  // A marker that stays in view but creeps 5 px over the frames (a subject standing nearly
  // still) is followed by one candidate all along, yet it is not static.
  std::vector<CameraFrame> frames = Frames({{200.0, 100.0, 12, 1.0}}, 60, 3);
  for (size_t f = 0; f < frames.size(); ++f) {
    Blob b;
    b.pixel = {500.0 + 0.08 * static_cast<double>(f), 300.0};
    b.area = 20;
    frames[f].blobs.push_back(b);
  }
  const CameraMask mask = ComputeAutoMask(frames, AutoMaskOptions{});
  ASSERT_EQ(mask.blobs.size(), 1u);
  EXPECT_NEAR(mask.blobs[0].x, 200.0, 0.1);
  EXPECT_FALSE(Covers(mask.regions, 502.0, 300.0));
  // With the bound lifted it is masked, drift and all: the bound is what keeps it out.
  AutoMaskOptions loose;
  loose.steady_radius_px = 10.0;
  const CameraMask all = ComputeAutoMask(frames, loose);
  EXPECT_EQ(all.blobs.size(), 2u);
  EXPECT_TRUE(Covers(all.regions, 502.0, 300.0));
}

TEST(AutoMask, RegionsAreClippedAndMerged) {
  const std::vector<Spot> spots = {{1.0, 1.0, 50, 1.0}, {1278.0, 798.0, 50, 1.0}, {600.0, 300.0, 50, 1.0},
                                   {606.0, 300.0, 50, 1.0}};
  const CameraMask mask = ComputeAutoMask(Frames(spots, 20, 2), AutoMaskOptions{});
  EXPECT_EQ(mask.blobs.size(), 4u);
  ASSERT_EQ(mask.regions.size(), 3u);  // the two close spots share one region
  for (const MaskRect& r : mask.regions) {
    EXPECT_LE(r.x + r.width, 1280u);
    EXPECT_LE(r.y + r.height, 800u);
  }
  EXPECT_EQ(mask.regions[0].x, 0u);
  EXPECT_EQ(mask.regions[2].x + mask.regions[2].width, 1280u);
}

TEST(AutoMask, RefusesTooFewOrMixedFrames) {
  EXPECT_THROW(ComputeAutoMask(Frames({}, 5, 1), AutoMaskOptions{}), std::invalid_argument);
  auto frames = Frames({}, 20, 1);
  frames[3].camera_id = 5;
  EXPECT_THROW(ComputeAutoMask(frames, AutoMaskOptions{}), std::invalid_argument);
  AutoMaskOptions bad;
  bad.min_presence = 0.0;
  EXPECT_THROW(ComputeAutoMask(Frames({}, 20, 1), bad), std::invalid_argument);
  AutoMaskOptions no_steady_radius;
  no_steady_radius.steady_radius_px = 0.0;
  EXPECT_THROW(ComputeAutoMask(Frames({}, 20, 1), no_steady_radius), std::invalid_argument);
}

CameraMask GridMask(int n) {
  CameraMask mask;
  mask.camera_id = 2;
  mask.width = 1280;
  mask.height = 800;
  for (int i = 0; i < n; ++i)
    mask.regions.push_back({static_cast<uint32_t>(13 + 71 * (i % 17)), static_cast<uint32_t>(7 + 83 * (i / 17)), 9, 5});
  return mask;
}

void ExpectValid(const std::vector<v1::Control>& commands) {
  for (const v1::Control& c : commands) {
    v1::Packet p;
    p.set_version(1);
    *p.mutable_control() = c;
    p.mutable_control()->set_node_id(1);
    EXPECT_EQ(wire::Validate(p), "");
  }
}

TEST(AutoMask, FewRegionsTravelAsRectangles) {
  const CameraMask mask = GridMask(16);
  const auto commands = MaskCommands(mask);
  ASSERT_EQ(commands.size(), 1u);
  ASSERT_EQ(commands[0].set_mask().rects_size(), 16);
  EXPECT_FALSE(commands[0].set_mask().clear());
  EXPECT_EQ(commands[0].set_mask().rects(5).x(), mask.regions[5].x);
  EXPECT_EQ(commands[0].set_mask().rects(5).height(), mask.regions[5].height);
  ExpectValid(commands);

  const auto clear = MaskCommands(CameraMask{2, 1280, 800, 0, {}, {}});
  ASSERT_EQ(clear.size(), 1u);
  EXPECT_TRUE(clear[0].set_mask().clear());
  EXPECT_EQ(clear[0].set_mask().rects_size(), 0);
}

TEST(AutoMask, ManyRegionsTravelAsTheCellImage) {
  const CameraMask mask = GridMask(60);
  const MaskBits bits = RasteriseMask(mask);
  EXPECT_EQ(bits.cell_px, 2u);  // 1 px cells would be 1 024 000, above the node's 262 144
  EXPECT_EQ(bits.cells_x, 640u);
  EXPECT_EQ(bits.cells_y, 400u);
  auto bit = [&](uint32_t px, uint32_t py) {
    const uint64_t i = uint64_t{py / bits.cell_px} * bits.cells_x + px / bits.cell_px;
    return (bits.bits[i >> 3] >> (i & 7)) & 1;
  };
  size_t set = 0;
  for (uint8_t b : bits.bits) set += static_cast<size_t>(__builtin_popcount(b));
  size_t cells = 0;
  for (const MaskRect& r : mask.regions) {
    for (uint32_t y = r.y; y < r.y + r.height; ++y)
      for (uint32_t x = r.x; x < r.x + r.width; ++x) EXPECT_EQ(bit(x, y), 1);
    cells += ((r.x + r.width - 1) / 2 - r.x / 2 + 1) * ((r.y + r.height - 1) / 2 - r.y / 2 + 1);
  }
  EXPECT_EQ(set, cells);  // nothing beyond the cells the regions touch

  const auto commands = MaskCommands(mask);
  ASSERT_EQ(commands.size(), (bits.bits.size() + 895) / 896);
  EXPECT_LE(commands.size(), 64u);
  std::string joined;
  for (size_t i = 0; i < commands.size(); ++i) {
    const v1::SetMask& m = commands[i].set_mask();
    EXPECT_EQ(m.chunk_index(), i);
    EXPECT_EQ(m.chunk_count(), commands.size());
    EXPECT_EQ(m.bit_offset(), i * 896 * 8);
    EXPECT_EQ(m.cell_px(), 2u);
    joined += m.bits();
  }
  EXPECT_EQ(joined, std::string(bits.bits.begin(), bits.bits.end()));
  ExpectValid(commands);

  NodeMaskLimits tiny;
  tiny.max_cells = 0;
  EXPECT_THROW(MaskCommands(mask, tiny), std::invalid_argument);
}

TEST(AutoMask, OnlyMasksWithRegionsOnCalibratedCamerasCount) {
  std::vector<CameraMask> masks(3);
  masks[0].camera_id = 1;
  masks[0].regions.push_back({0, 0, 8, 8});
  masks[1].camera_id = 2;  // found nothing static
  masks[2].camera_id = 9;  // kept for a camera the calibration no longer has
  masks[2].regions.push_back({0, 0, 8, 8});
  Rig rig;
  EXPECT_EQ(CountMaskedCameras(masks, rig), 2u);  // no calibration yet: every camera counts
  for (uint32_t id : {1u, 2u, 3u}) {
    rig.cameras.emplace_back();
    rig.cameras.back().id = id;
  }
  EXPECT_EQ(CountMaskedCameras(masks, rig), 1u);
}

TEST(AutoMask, FileRoundTripAndBadFiles) {
  const CameraMask found = ComputeAutoMask(Frames({{200.0, 100.0, 12, 1.0}}, 20, 3), AutoMaskOptions{});
  const std::vector<CameraMask> masks = {found, GridMask(3)};
  const nlohmann::json doc = nlohmann::json::parse(MasksToJson(masks).dump());
  const auto back = MasksFromJson(doc, "masks.json");
  ASSERT_EQ(back.size(), 2u);
  EXPECT_EQ(back[0].camera_id, found.camera_id);
  EXPECT_EQ(back[0].frames, 20u);
  EXPECT_EQ(back[0].regions, found.regions);
  ASSERT_EQ(back[0].blobs.size(), 1u);
  EXPECT_DOUBLE_EQ(back[0].blobs[0].x, found.blobs[0].x);
  EXPECT_EQ(back[1].regions, masks[1].regions);
  EXPECT_EQ(MaskCommands(back[1])[0].DebugString(), MaskCommands(masks[1])[0].DebugString());

  auto expect_error = [](const std::string& text, const std::string& part) {
    try {
      MasksFromJson(nlohmann::json::parse(text), "m.json");
      ADD_FAILURE() << "accepted " << text;
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << e.what();
      EXPECT_EQ(std::string(e.what()).rfind("m.json", 0), 0u) << e.what();
    }
  };
  expect_error(R"({"cameras": []})", "version");
  expect_error(R"({"version": 2, "cameras": []})", "version");
  expect_error(R"({"version": 1, "cameras": {}})", "array");
  expect_error(R"({"version": 1, "cameras": [{"camera_id": 1, "width": 10, "height": 10,
                 "regions": [{"x": 5, "y": 5, "width": 6, "height": 1}]}]})", "outside");
  expect_error(R"({"version": 1, "cameras": [{"camera_id": 1, "width": 10, "height": 10, "regions": []},
                 {"camera_id": 1, "width": 10, "height": 10, "regions": []}]})", "unique");
  expect_error(R"({"version": 1, "cameras": [{"camera_id": "one", "width": 10, "height": 10, "regions": []}]})",
               "wrong type");
  expect_error(R"({"version": 1, "cameras": [{"camera_id": 1, "width": 10, "height": 10}]})", "regions");
  // Numbers the field's integer type cannot hold are refused naming the field, not converted: the
  // masks-file fuzzer's "width": 1e71 was undefined behaviour, a camera_id of -1 wrapped to
  // 4294967295 and a width of 2^32 + 10 to 10.
  expect_error(R"({"version": 1, "cameras": [{"camera_id": 1, "width": 1e71, "height": 10, "regions": []}]})",
               "\"width\" must be an integer from 0 to 4294967295");
  expect_error(R"({"version": 1, "cameras": [{"camera_id": -1, "width": 10, "height": 10, "regions": []}]})",
               "\"camera_id\" must be an integer");
  expect_error(R"({"version": 1, "cameras": [{"camera_id": 1, "width": 4294967306, "height": 10, "regions": []}]})",
               "\"width\" must be an integer");
  expect_error(R"({"version": 1, "cameras": [{"camera_id": 1, "width": 10.5, "height": 10, "regions": []}]})",
               "\"width\" must be an integer");
  expect_error(R"({"version": 1, "cameras": [{"camera_id": 1, "width": 10, "height": 10, "frames": -3, "regions": []}]})",
               "\"frames\" must be an integer");
  expect_error(R"({"version": 1, "cameras": [{"camera_id": 1, "width": 10, "height": 10,
                 "regions": [{"x": 1e30, "y": 0, "width": 1, "height": 1}]}]})", "\"x\" must be an integer");
  expect_error(R"({"version": 1e40, "cameras": []})", "\"version\" must be an integer");
}

}  // namespace
}  // namespace mocap::service

// OSC: the address space of a frame's bundle, and a real bundle received by liblo's own
// server on loopback with every value in place. (The test suite's python-osc receiver checks
// the same against an independent OSC implementation.)
#include "stream/osc_sender.h"

#include <lo/lo.h>

#include <chrono>
#include <thread>

#include <gtest/gtest.h>

namespace mocap::stream {
namespace {

pipeline::LiveFrame Frame() {
  pipeline::LiveFrame f;
  f.frame_number = 77;
  f.trigger_time_ns = 1'800'000'000'000'000'123ull;
  pipeline::LivePoint confirmed;
  confirmed.position = {10.0, 20.0, 30.0};
  confirmed.rms_px = 0.5;
  confirmed.views = 3;
  confirmed.marker = 4;
  confirmed.id = 9;
  pipeline::LivePoint provisional;
  provisional.position = {-1.0, -2.0, -3.0};
  provisional.views = 2;
  provisional.id = 12;
  pipeline::LivePoint untracked;
  untracked.views = 2;
  f.points = {confirmed, provisional, untracked};
  pipeline::LiveBody body;
  body.name = "wand";
  body.tracked = true;
  body.position = {1.0, 2.0, 3.0};
  pipeline::LiveBody lost;
  lost.name = "lost";
  f.bodies = {body, lost};
  return f;
}

TEST(OscSender, AddressSpace) {
  const auto shape = OscBundleShape(Frame(), kPartPoints | kPartBodies);
  ASSERT_EQ(shape.size(), 5u);
  EXPECT_EQ(shape[0].path, "/mocap/frame");
  EXPECT_EQ(shape[0].types, "hhii");
  EXPECT_EQ(shape[1].path, "/mocap/marker");
  EXPECT_EQ(shape[1].types, "iffffi");
  EXPECT_EQ(shape[2].path, "/mocap/point");
  EXPECT_EQ(shape[2].types, "hffffi");
  EXPECT_EQ(shape[3].path, "/mocap/point");
  EXPECT_EQ(shape[4].path, "/mocap/rigidbody");  // the lost body is left out
  EXPECT_EQ(shape[4].types, "sffffffff");
  EXPECT_EQ(OscBundleShape(Frame(), kPartBodies).size(), 2u);
  // With a marker set every point message ends with the point's name.
  pipeline::LiveFrame named = Frame();
  named.label_names = std::make_shared<const std::vector<std::string>>(std::vector<std::string>{"Head"});
  const auto named_shape = OscBundleShape(named, kPartPoints);
  EXPECT_EQ(named_shape[1].types, "iffffis");
  EXPECT_EQ(named_shape[2].types, "hffffis");
  // Bones only with their part: a skeleton message each, a bone message per bone when solved.
  pipeline::LiveFrame skeletal = Frame();
  auto model = std::make_shared<pipeline::LiveSkeletonModel>();
  model->bones = {"Hips", "Spine"};
  model->parents = {-1, 0};
  pipeline::LiveSkeleton solved;
  solved.model = model;
  solved.solved = true;
  solved.bones.resize(2);
  pipeline::LiveSkeleton unsolved;
  unsolved.model = model;
  skeletal.skeletons = {solved, unsolved};
  EXPECT_EQ(OscBundleShape(skeletal, kPartBodies).size(), 2u);
  const auto bones = OscBundleShape(skeletal, kPartBones);
  ASSERT_EQ(bones.size(), 5u);
  EXPECT_EQ(bones[1].path, "/mocap/skeleton");
  EXPECT_EQ(bones[1].types, "sisiff");
  EXPECT_EQ(bones[2].path, "/mocap/bone");
  EXPECT_EQ(bones[2].types, "ssifffffff");
  EXPECT_EQ(bones[3].path, "/mocap/bone");
  EXPECT_EQ(bones[4].path, "/mocap/skeleton");  // unsolved: no bones
  pipeline::LiveFrame many;
  many.points.resize(kMaxOscPoints + 10);
  EXPECT_EQ(OscBundleShape(many, kPartPoints).size(), 1 + kMaxOscPoints);
}

struct Received {
  std::vector<std::string> paths;
  std::vector<std::vector<double>> numbers;
  std::vector<std::string> strings;
};

int OnMessage(const char* path, const char* types, lo_arg** argv, int argc, lo_message, void* user) {
  auto* r = static_cast<Received*>(user);
  r->paths.push_back(path);
  std::vector<double> numbers;
  for (int i = 0; i < argc; ++i) {
    switch (types[i]) {
      case 'i': numbers.push_back(argv[i]->i); break;
      case 'h': numbers.push_back(static_cast<double>(argv[i]->h)); break;
      case 'f': numbers.push_back(argv[i]->f); break;
      case 's': r->strings.push_back(&argv[i]->s); break;
      default: break;
    }
  }
  r->numbers.push_back(numbers);
  return 0;
}

TEST(OscSender, LibloReceivesTheBundle) {
  lo_server server = lo_server_new_with_proto(nullptr, LO_UDP, nullptr);
  ASSERT_NE(server, nullptr);
  Received received;
  lo_server_add_method(server, nullptr, nullptr, OnMessage, &received);
  OscOptions options;
  options.targets = {"127.0.0.1:" + std::to_string(lo_server_get_port(server))};
  {
    OscSender sender(options);
    sender.Publish(ShareFrame(Frame()));
    for (int i = 0; i < 50 && received.paths.size() < 5; ++i) lo_server_recv_noblock(server, 100);
    // The sender counts the bundle once its send returned, which may be after it arrived.
    for (int i = 0; i < 100 && sender.stats().bundles == 0; ++i)
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    EXPECT_EQ(sender.stats().bundles, 1u);
  }
  lo_server_free(server);
  ASSERT_EQ(received.paths.size(), 5u);
  EXPECT_EQ(received.paths[0], "/mocap/frame");
  EXPECT_EQ(received.numbers[0][0], 77.0);
  EXPECT_EQ(received.numbers[0][2], 3.0);  // points
  EXPECT_EQ(received.numbers[0][3], 1.0);  // tracked bodies
  EXPECT_EQ(received.numbers[1], (std::vector<double>{9, 10, 20, 30, 0.5, 3}));  // its track's id
  EXPECT_EQ(received.numbers[2][0], 12.0);
  EXPECT_EQ(received.numbers[3][0], -1.0);
  EXPECT_EQ(received.strings, std::vector<std::string>{"wand"});
  EXPECT_EQ(received.numbers[4][2], 3.0);  // z of the body
  EXPECT_EQ(received.numbers[4][6], 1.0);  // qw of the identity
}

TEST(OscSender, OptionsChecked) {
  OscOptions o;
  EXPECT_THROW(OscSender{o}, std::invalid_argument);
  o.targets = {"nohost"};
  EXPECT_THROW(OscSender{o}, std::invalid_argument);
  o.targets = {"127.0.0.1:9000"};
  o.parts = kPartLabels;
  EXPECT_THROW(OscSender{o}, std::invalid_argument);
}

}  // namespace
}  // namespace mocap::stream

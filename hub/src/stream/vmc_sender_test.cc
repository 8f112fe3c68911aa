// VMC: the world -> Unity map for every up axis (a reflection that puts up on Unity's Y, and
// rotations conjugated so that a rotated vector maps to the mapped rotation of the mapped
// vector), a frame's bundle (OK, T, one tracker per fitted body, in metres), and a real bundle
// that liblo's server on loopback can read as soon as Publish returns (it is sent on the
// publishing thread). (python-osc, an independent OSC implementation, reads serve --vmc in
// tests/stream/natnet_vrpn_vmc_test.py.)
#include "stream/vmc_sender.h"

#include <lo/lo.h>


#include <Eigen/Geometry>
#include <gtest/gtest.h>

namespace mocap::stream {
namespace {

TEST(VmcAxes, PutUpOnUnityYAsAReflection) {
  for (const char* up : {"+X", "-X", "+Y", "-Y", "+Z", "-Z"}) {
    SCOPED_TRACE(up);
    const Eigen::Matrix3d m = VmcAxes(up);
    EXPECT_NEAR(m.determinant(), -1.0, 1e-12);
    EXPECT_TRUE((m * m.transpose()).isApprox(Eigen::Matrix3d::Identity()));
    Eigen::Vector3d u = Eigen::Vector3d::Zero();
    u[up[1] - 'X'] = up[0] == '+' ? 1 : -1;
    EXPECT_TRUE((m * u).isApprox(Eigen::Vector3d::UnitY()));
  }
  // Y up: z flips; Z up: y and z swap.
  EXPECT_TRUE((VmcAxes("+Y") * Eigen::Vector3d(1, 2, 3)).isApprox(Eigen::Vector3d(1, 2, -3)));
  EXPECT_TRUE((VmcAxes("+Z") * Eigen::Vector3d(1, 2, 3)).isApprox(Eigen::Vector3d(1, 3, 2)));
  VmcOptions o;
  o.target = "127.0.0.1:39539";
  o.rate_hz = 100;
  o.up_axis = "Y";
  EXPECT_THROW(o.Check(), std::invalid_argument);
}

pipeline::LiveFrame Frame() {
  pipeline::LiveFrame f;
  f.frame_number = 250;
  pipeline::LiveBody fitted;
  fitted.name = "drone";
  fitted.tracked = true;
  fitted.position = {100, 2000, -300};
  fitted.orientation = Eigen::Quaterniond(Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()));
  pipeline::LiveBody lost;
  lost.name = "lost";
  f.bodies = {fitted, lost};
  return f;
}

TEST(VmcBundle, TrackersInUnityMetres) {
  VmcOptions o;
  o.target = "127.0.0.1:39539";
  o.rate_hz = 100;
  o.up_axis = "+Z";
  const pipeline::LiveFrame f = Frame();
  const auto bundle = VmcBundle(f, o);
  ASSERT_EQ(bundle.size(), 3u);  // the lost body is left out
  EXPECT_EQ(bundle[0].path, "/VMC/Ext/OK");
  EXPECT_EQ(bundle[0].ints, (std::vector<int>{1, 3, 0, 1}));
  EXPECT_EQ(bundle[1].path, "/VMC/Ext/T");
  EXPECT_FLOAT_EQ(bundle[1].floats[0], 2.5f);
  const VmcMessage& t = bundle[2];
  EXPECT_EQ(t.path, "/VMC/Ext/Tra/Pos");
  EXPECT_EQ(t.types, "sfffffff");
  EXPECT_EQ(t.text, "drone");
  EXPECT_FLOAT_EQ(t.floats[0], 0.1f);   // x
  EXPECT_FLOAT_EQ(t.floats[1], -0.3f);  // world z is up
  EXPECT_FLOAT_EQ(t.floats[2], 2.0f);   // world y
  const Eigen::Matrix3d m = VmcAxes("+Z");
  const Eigen::Quaterniond q(t.floats[6], t.floats[3], t.floats[4], t.floats[5]);
  const Eigen::Vector3d v(0.3, -1.2, 0.8);
  EXPECT_TRUE((q * (m * v)).isApprox(m * (f.bodies[0].orientation * v), 1e-6));
  pipeline::LiveFrame none = Frame();
  none.bodies[0].tracked = false;
  EXPECT_EQ(VmcBundle(none, o)[0].ints[3], 0);
}

// A skeleton at our rest pose (arms hanging) in a z-up world, the subject turned about the
// vertical, its left elbow bent 90 deg; segments: Hips, Spine, LeftShoulder, LeftArm,
// LeftForeArm, Tail (no humanoid name, under Spine), RightUpLeg.
pipeline::LiveFrame SkeletonFrame(bool solved) {
  pipeline::LiveFrame f;
  f.frame_number = 100;
  auto model = std::make_shared<pipeline::LiveSkeletonModel>();
  model->name = "anna";
  model->bones = {"Hips", "Spine", "LeftShoulder", "LeftArm", "LeftForeArm", "Tail", "RightUpLeg"};
  model->parents = {-1, 0, 1, 2, 3, 1, 0};
  pipeline::LiveSkeleton s;
  s.model = model;
  s.solved = solved;
  if (solved) {
    Eigen::Matrix3d world_from_skeleton;
    world_from_skeleton << 1, 0, 0, 0, 0, -1, 0, 1, 0;  // +y up -> +z up
    const Eigen::Matrix3d turned = Eigen::AngleAxisd(0.4, Eigen::Vector3d::UnitZ()) * world_from_skeleton;
    const Eigen::Vector3d skeleton_positions[] = {{0, 1000, 0},  {0, 1100, 0},  {30, 1500, 0}, {180, 1500, 0},
                                                  {180, 1200, 0}, {0, 1100, -50}, {-90, 1000, 0}};
    for (size_t b = 0; b < model->bones.size(); ++b) {
      pipeline::LiveBone bone;
      bone.position = turned * skeleton_positions[b] + Eigen::Vector3d(500, -200, 0);
      Eigen::Matrix3d r = turned;
      if (model->bones[b] == "LeftForeArm") r = turned * Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitX());
      bone.orientation = Eigen::Quaterniond(r);
      s.bones.push_back(bone);
    }
  }
  f.skeletons = {s};
  return f;
}

Eigen::Quaterniond QuaternionOf(const VmcMessage& m) {
  return Eigen::Quaterniond(m.floats[6], m.floats[3], m.floats[4], m.floats[5]);
}

TEST(VmcBundle, SkeletonRootAndHumanoidBones) {
  VmcOptions o;
  o.target = "127.0.0.1:39539";
  o.rate_hz = 100;
  o.up_axis = "+Z";
  const auto bundle = VmcBundle(SkeletonFrame(true), o);
  std::vector<std::string> names;
  for (const VmcMessage& m : bundle) names.push_back(m.path + " " + m.text);
  EXPECT_EQ(names, (std::vector<std::string>{"/VMC/Ext/OK ", "/VMC/Ext/T ", "/VMC/Ext/Root/Pos root",
                                             "/VMC/Ext/Bone/Pos Hips", "/VMC/Ext/Bone/Pos Spine",
                                             "/VMC/Ext/Bone/Pos LeftShoulder", "/VMC/Ext/Bone/Pos LeftUpperArm",
                                             "/VMC/Ext/Bone/Pos LeftLowerArm", "/VMC/Ext/Bone/Pos RightUpperLeg"}));
  EXPECT_EQ(bundle[0].ints[3], 1);  // tracking: the skeleton is solved
  // Root: the hips in Unity metres (x, up, world y), turned about Unity's up only.
  const VmcMessage& root = bundle[2];
  EXPECT_EQ(root.types, "sfffffff");
  EXPECT_NEAR(root.floats[1], 1.0, 1e-6);  // the hips 1 m above the floor: Unity up
  const Eigen::Vector3d up = QuaternionOf(root) * Eigen::Vector3d::UnitY();
  EXPECT_TRUE(up.isApprox(Eigen::Vector3d::UnitY(), 1e-6));
  EXPECT_TRUE(QuaternionOf(bundle[3]).isApprox(Eigen::Quaterniond::Identity()));  // Hips
  for (int i = 0; i < 3; ++i) EXPECT_EQ(bundle[3].floats[static_cast<size_t>(i)], 0.0f);
  // Spine: identity at rest, 0.1 m up from the hips.
  EXPECT_LT(QuaternionOf(bundle[4]).angularDistance(Eigen::Quaterniond::Identity()), 1e-5);
  EXPECT_NEAR(bundle[4].floats[0], 0.0, 1e-6);
  EXPECT_NEAR(bundle[4].floats[1], 0.1, 1e-6);
  EXPECT_NEAR(bundle[4].floats[2], 0.0, 1e-6);
  // The hanging upper arm: a T-pose's left arm (avatar -x) turned down (-y).
  EXPECT_TRUE((QuaternionOf(bundle[6]) * Eigen::Vector3d(-1, 0, 0)).isApprox(Eigen::Vector3d(0, -1, 0), 1e-5));
  // The elbow bent 90 deg: in the T-pose's frame a turn of 90 deg about the vertical.
  const Eigen::AngleAxisd elbow(QuaternionOf(bundle[7]));
  EXPECT_NEAR(elbow.angle(), M_PI / 2, 1e-5);
  EXPECT_NEAR(std::fabs(elbow.axis().y()), 1.0, 1e-5);
  // RightUpperLeg: relative to the hips, 9 cm to the avatar's right (+x in Unity).
  EXPECT_NEAR(bundle[8].floats[0], 0.09, 1e-6);
  // Not solved: no root, no bones, not tracking.
  const auto unsolved = VmcBundle(SkeletonFrame(false), o);
  EXPECT_EQ(unsolved.size(), 2u);
  EXPECT_EQ(unsolved[0].ints[3], 0);
  EXPECT_STREQ(VmcHumanoidBone("LeftUpLeg"), "LeftUpperLeg");
  EXPECT_EQ(VmcHumanoidBone("Tail"), nullptr);
}

struct Received {
  std::vector<std::string> paths;
  std::string tracker;
  float y = 0;
};

int OnMessage(const char* path, const char*, lo_arg** argv, int argc, lo_message, void* user) {
  auto* r = static_cast<Received*>(user);
  r->paths.push_back(path);
  if (std::string(path) == "/VMC/Ext/Tra/Pos" && argc == 8) {
    r->tracker = &argv[0]->s;
    r->y = argv[2]->f;
  }
  return 0;
}

TEST(VmcSender, SendsABundleLibloReceivesBeforePublishReturns) {
  lo_server server = lo_server_new_with_proto(nullptr, LO_UDP, nullptr);
  ASSERT_NE(server, nullptr);
  Received got;
  lo_server_add_method(server, nullptr, nullptr, OnMessage, &got);
  VmcOptions o;
  o.target = "127.0.0.1:" + std::to_string(lo_server_get_port(server));
  o.rate_hz = 100;
  {
    VmcSender sender(o);
    sender.Publish(std::make_shared<pipeline::LiveFrame>(Frame()));
    // Sent on the publishing thread: the kernel holds the datagram when Publish returns.
    EXPECT_EQ(sender.stats().bundles, 1u);
    EXPECT_EQ(lo_server_recv_noblock(server, 0) > 0, true);
    EXPECT_EQ(sender.stats().send_failures, 0u);
  }
  lo_server_free(server);
  EXPECT_EQ(got.paths, (std::vector<std::string>{"/VMC/Ext/OK", "/VMC/Ext/T", "/VMC/Ext/Tra/Pos"}));
  EXPECT_EQ(got.tracker, "drone");
  EXPECT_FLOAT_EQ(got.y, 2.0f);  // +Y up by default
}

}  // namespace
}  // namespace mocap::stream

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

// VMC (Virtual Motion Capture's OSC protocol, read by VSeeFace, the VMC4U/VMC4B receivers and
// Unity/Blender tools) from `mocap-hub serve --vmc HOST:PORT`: every published frame as one OSC
// bundle (liblo) of
//   /VMC/Ext/OK       i:1 (loaded) i:3 (calibrated) i:0 (normal calibration) i:tracking
//                     (1 when a rigid body is fitted or the skeleton solved in the frame, else 0)
//   /VMC/Ext/T        f:the frame's capture time, s since the session epoch (frame number / rate)
//   /VMC/Ext/Tra/Pos  s:body name f:x f:y f:z f:qx f:qy f:qz f:qw     (each fitted rigid body)
// in Unity's frame as VMC defines it: metres, left-handed, Y up. The hub's world (right-handed,
// its up axis read from the cameras as for Qualisys RT) maps onto it by a reflection: Unity X
// is world +X (+Y when up is ±X), Unity Y is world up, Unity Z = -(X × Y) in world terms;
// rotations are conjugated by the same map (vmc_axes in the .cc).
// With serve --skeleton, in frames where it is solved (the first skeleton):
//   /VMC/Ext/Root/Pos s:"root" f:x f:y f:z f:qx f:qy f:qz f:qw   the root segment's (Hips) pose
//   /VMC/Ext/Bone/Pos s:bone   f:x f:y f:z f:qx f:qy f:qz f:qw   per segment with a humanoid name
// Bones are Unity's HumanBodyBones names mapped from our segments (VmcHumanoidBone; segments
// without one are left out, their children taken from the nearest named ancestor), each with
// its local position and rotation against that ancestor (Hips: zero and identity, the root
// carries its pose). Rotations are those of a humanoid whose rest pose (identity) is the T-pose
// VMC avatars use: each bone's frame is the segment's in Unity's avatar axes (x flipped: the
// avatar's +x is its right), the arms' turned by 90 deg about the forward axis (our rest pose
// has them hanging, thumbs forward).
//
// Threads: none of its own. Publish() (the hub's loop) builds the bundle (liblo) and hands it to
// the kernel at once from a non-blocking socket (a few microseconds: one target, one datagram,
// no thread hand-over between the frame's publish and its send); a datagram the kernel will not
// take is counted, never waited for. stats() from any thread.
// Errors: the constructor throws std::invalid_argument for a bad target or up axis.
#pragma once

#include <netinet/in.h>

#include <cstdint>
#include <mutex>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json_fwd.hpp>

#include "ingest/udp_socket.h"
#include "stream/stream_sink.h"
#include "stream/publish_latency.h"

namespace mocap::stream {

struct VmcOptions {
  std::string target;            // HOST:PORT (VMC receivers listen on 39539 by default)
  std::string up_axis = "+Y";    // the hub world's up: "+X", "-X", "+Y", "-Y", "+Z", "-Z"
  double rate_hz = 0.0;          // serve's --rate (for /VMC/Ext/T)

  void Check() const;  // throws std::invalid_argument
};

// Unity's HumanBodyBones name of one of our segments (skeleton templates' names), or null.
const char* VmcHumanoidBone(const std::string& segment);

// The world -> Unity map of an up axis (a reflection: determinant -1).
Eigen::Matrix3d VmcAxes(const std::string& up_axis);

struct VmcMessage {
  std::string path;
  std::string types;
  std::vector<float> floats;  // f arguments in order
  std::vector<int> ints;      // i arguments in order
  std::string text;           // the s argument, if any
};
// The messages of one frame's bundle, in order: what the sender sends (tests read it here).
std::vector<VmcMessage> VmcBundle(const pipeline::LiveFrame& frame, const VmcOptions& options);

struct VmcStats {
  uint64_t bundles = 0;
  uint64_t send_failures = 0;  // bundles the kernel did not take (a full socket buffer, no route)
};

class VmcSender : public StreamSink {
 public:
  explicit VmcSender(VmcOptions options);
  ~VmcSender() override = default;
  VmcSender(const VmcSender&) = delete;
  VmcSender& operator=(const VmcSender&) = delete;

  void Publish(SharedFrame frame) override;
  VmcStats stats() const;
  nlohmann::json StatsJson() const override;

 private:
  const VmcOptions options_;
  UdpSocket socket_;
  sockaddr_in target_{};
  std::vector<uint8_t> datagram_;  // the loop's own
  mutable std::mutex stats_mutex_;
  VmcStats stats_;
  PublishLatency latency_;  // under stats_mutex_
};

}  // namespace mocap::stream

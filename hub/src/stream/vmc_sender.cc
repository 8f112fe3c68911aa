// VMC bundles per frame, encoded by liblo and sent on the hub's loop (see vmc_sender.h).
#include "stream/vmc_sender.h"
#include "stream/publish_latency.h"

#include <lo/lo.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

namespace mocap::stream {
namespace {

constexpr double kMetresPerMm = 1e-3;

Eigen::Vector3d AxisOf(const std::string& up) {
  if (up.size() != 2 || (up[0] != '+' && up[0] != '-') || up[1] < 'X' || up[1] > 'Z')
    throw std::invalid_argument("VMC up axis '" + up + "' must be one of +X -X +Y -Y +Z -Z");
  Eigen::Vector3d axis = Eigen::Vector3d::Zero();
  axis[up[1] - 'X'] = up[0] == '+' ? 1.0 : -1.0;
  return axis;
}

// Our segments (skeleton/skeleton_template.h's names) -> Unity's HumanBodyBones.
constexpr const char* kHumanoidBones[][2] = {
    {"Hips", "Hips"},
    {"Spine", "Spine"},
    {"Chest", "Chest"},
    {"Neck", "Neck"},
    {"Head", "Head"},
    {"LeftShoulder", "LeftShoulder"},
    {"LeftArm", "LeftUpperArm"},
    {"LeftForeArm", "LeftLowerArm"},
    {"LeftHand", "LeftHand"},
    {"RightShoulder", "RightShoulder"},
    {"RightArm", "RightUpperArm"},
    {"RightForeArm", "RightLowerArm"},
    {"RightHand", "RightHand"},
    {"LeftUpLeg", "LeftUpperLeg"},
    {"LeftLeg", "LeftLowerLeg"},
    {"LeftFoot", "LeftFoot"},
    {"LeftToeBase", "LeftToes"},
    {"RightUpLeg", "RightUpperLeg"},
    {"RightLeg", "RightLowerLeg"},
    {"RightFoot", "RightFoot"},
    {"RightToeBase", "RightToes"},
};

// The rest-pose difference on a humanoid bone, in its Unity frame: a T-pose's arm (out to the
// side) turned into ours (hanging, thumbs forward), about the avatar's forward axis.
Eigen::Matrix3d RestCorrection(const std::string& humanoid) {
  const bool arm = humanoid.find("UpperArm") != std::string::npos || humanoid.find("LowerArm") != std::string::npos ||
                   humanoid == "LeftHand" || humanoid == "RightHand";
  if (!arm) return Eigen::Matrix3d::Identity();
  const double angle = humanoid.rfind("Left", 0) == 0 ? M_PI / 2 : -M_PI / 2;
  return Eigen::AngleAxisd(angle, Eigen::Vector3d::UnitZ()).toRotationMatrix();
}

void AddPose(const char* path, const std::string& name, const Eigen::Vector3d& p, const Eigen::Matrix3d& r,
             std::vector<VmcMessage>* out) {
  const Eigen::Quaterniond q(r);
  out->push_back({path,
                  "sfffffff",
                  {static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z()),
                   static_cast<float>(q.x()), static_cast<float>(q.y()), static_cast<float>(q.z()),
                   static_cast<float>(q.w())},
                  {},
                  name});
}

// Root and bones of a solved skeleton (see vmc_sender.h).
void AddSkeleton(const pipeline::LiveSkeleton& skeleton, const Eigen::Matrix3d& m, std::vector<VmcMessage>* out) {
  const pipeline::LiveSkeletonModel& model = *skeleton.model;
  const size_t n = std::min(model.bones.size(), skeleton.bones.size());
  // Skeleton space (+x the subject's left) -> Unity's avatar axes (+x its right).
  const Eigen::Matrix3d flip = Eigen::Vector3d(-1, 1, 1).asDiagonal();
  std::vector<const char*> humanoid(n, nullptr);
  std::vector<Eigen::Matrix3d> unity(n);
  for (size_t b = 0; b < n; ++b) {
    for (const auto& pair : kHumanoidBones)
      if (model.bones[b] == pair[0]) humanoid[b] = pair[1];
    unity[b] = m * skeleton.bones[b].orientation.normalized().toRotationMatrix() * flip *
               (humanoid[b] ? RestCorrection(humanoid[b]) : Eigen::Matrix3d::Identity());
  }
  if (n == 0) return;
  AddPose("/VMC/Ext/Root/Pos", "root", m * skeleton.bones[0].position * kMetresPerMm, unity[0], out);
  for (size_t b = 0; b < n; ++b) {
    if (!humanoid[b]) continue;
    if (b == 0) {
      AddPose("/VMC/Ext/Bone/Pos", humanoid[b], Eigen::Vector3d::Zero(), Eigen::Matrix3d::Identity(), out);
      continue;
    }
    // Relative to the nearest ancestor with a humanoid name.
    int parent = model.parents[b];
    while (parent > 0 && !humanoid[static_cast<size_t>(parent)]) parent = model.parents[static_cast<size_t>(parent)];
    if (parent < 0) continue;
    const size_t a = static_cast<size_t>(parent);
    const Eigen::Vector3d offset = m * (skeleton.bones[b].position - skeleton.bones[a].position) * kMetresPerMm;
    AddPose("/VMC/Ext/Bone/Pos", humanoid[b], unity[a].transpose() * offset, unity[a].transpose() * unity[b], out);
  }
}

}  // namespace

const char* VmcHumanoidBone(const std::string& segment) {
  for (const auto& pair : kHumanoidBones)
    if (segment == pair[0]) return pair[1];
  return nullptr;
}

Eigen::Matrix3d VmcAxes(const std::string& up_axis) {
  const Eigen::Vector3d u = AxisOf(up_axis);
  const Eigen::Vector3d r = u.x() != 0.0 ? Eigen::Vector3d::UnitY() : Eigen::Vector3d::UnitX();
  const Eigen::Vector3d f = -r.cross(u);
  Eigen::Matrix3d m;
  m.row(0) = r.transpose();
  m.row(1) = u.transpose();
  m.row(2) = f.transpose();
  return m;
}

void VmcOptions::Check() const {
  const HostPort hp = ParseHostPort(target);
  if (hp.host.empty() || hp.port == 0) throw std::invalid_argument("VMC target '" + target + "' must be HOST:PORT");
  AxisOf(up_axis);
  if (!(rate_hz > 0.0)) throw std::invalid_argument("VMC: rate must be > 0 Hz");
}

std::vector<VmcMessage> VmcBundle(const pipeline::LiveFrame& frame, const VmcOptions& options) {
  const Eigen::Matrix3d m = VmcAxes(options.up_axis);
  int tracked = 0;
  for (const pipeline::LiveBody& b : frame.bodies) tracked += b.tracked;
  const pipeline::LiveSkeleton* skeleton =
      !frame.skeletons.empty() && frame.skeletons[0].solved && frame.skeletons[0].model ? &frame.skeletons[0] : nullptr;
  tracked += skeleton != nullptr;
  std::vector<VmcMessage> out;
  out.push_back({"/VMC/Ext/OK", "iiii", {}, {1, 3, 0, tracked > 0 ? 1 : 0}, ""});
  out.push_back({"/VMC/Ext/T", "f", {static_cast<float>(static_cast<double>(frame.frame_number) / options.rate_hz)}, {}, ""});
  for (const pipeline::LiveBody& b : frame.bodies) {
    if (!b.tracked) continue;
    const Eigen::Vector3d p = m * b.position * kMetresPerMm;
    const Eigen::Quaterniond q(Eigen::Matrix3d(m * b.orientation.normalized().toRotationMatrix() * m.transpose()));
    out.push_back({"/VMC/Ext/Tra/Pos",
                   "sfffffff",
                   {static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z()),
                    static_cast<float>(q.x()), static_cast<float>(q.y()), static_cast<float>(q.z()),
                    static_cast<float>(q.w())},
                   {},
                   b.name});
  }
  if (skeleton) AddSkeleton(*skeleton, m, &out);
  return out;
}

namespace {

// One frame's bundle as liblo encodes it, into `out`; false when liblo cannot.
bool SerialiseBundle(const std::vector<VmcMessage>& messages, std::vector<uint8_t>* out) {
  lo_bundle bundle = lo_bundle_new(LO_TT_IMMEDIATE);
  for (const VmcMessage& v : messages) {
    lo_message msg = lo_message_new();
    size_t f = 0, i = 0;
    for (char t : v.types) {
      if (t == 's') lo_message_add_string(msg, v.text.c_str());
      else if (t == 'f') lo_message_add_float(msg, v.floats[f++]);
      else lo_message_add_int32(msg, v.ints[i++]);
    }
    lo_bundle_add_message(bundle, v.path.c_str(), msg);
  }
  size_t size = lo_bundle_length(bundle);
  out->resize(size);
  const bool ok = size > 0 && lo_bundle_serialise(bundle, out->data(), &size) != nullptr;
  out->resize(ok ? size : 0);
  lo_bundle_free_recursive(bundle);
  return ok;
}

}  // namespace

VmcSender::VmcSender(VmcOptions options) : options_((options.Check(), std::move(options))) {
  try {
    target_ = ResolveHostPort(ParseHostPort(options_.target));
    socket_.Bind(HostPort{"", 0});  // any address, a port of the kernel's choosing
  } catch (const std::exception& error) {
    throw std::invalid_argument("VMC target '" + options_.target + "': " + error.what());
  }
}

VmcStats VmcSender::stats() const {
  std::lock_guard<std::mutex> lock(stats_mutex_);
  return stats_;
}

nlohmann::json VmcSender::StatsJson() const {
  std::lock_guard<std::mutex> lock(stats_mutex_);
  nlohmann::json out = {{"target", options_.target},
                        {"up_axis", options_.up_axis},
                        {"bundles", stats_.bundles},
                        {"send_failures", stats_.send_failures}};
  out.update(latency_.Json("VMC bundle"));
  return out;
}

void VmcSender::Publish(SharedFrame frame) {
  const uint64_t began_ns = RealtimeNowNs();
  const bool sent = SerialiseBundle(VmcBundle(*frame, options_), &datagram_) &&
                    socket_.SendTo(target_, datagram_.data(), datagram_.size());
  const uint64_t done_ns = RealtimeNowNs();
  std::lock_guard<std::mutex> lock(stats_mutex_);
  (sent ? stats_.bundles : stats_.send_failures)++;
  if (sent) latency_.Add(frame->publish_ns, began_ns, done_ns);
}

}  // namespace mocap::stream

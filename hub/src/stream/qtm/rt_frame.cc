// Data packet encoding (see rt_frame.h).
#include "stream/qtm/rt_frame.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "stream/qtm/rt_command.h"
#include "stream/qtm/rt_packet.h"

namespace mocap::stream::qtm {
namespace {

// The protocol's "missing" value: a float with all bits set.
void PutMissing(std::string* out) { PutU32(out, 0xffffffffu); }

void PutVector(std::string* out, const Eigen::Vector3d& v) {
  for (int i = 0; i < 3; ++i) PutF32(out, static_cast<float>(v[i]));
}

// Point id of 3D no labels (rt_frame.h).
uint32_t PointId(const pipeline::LivePoint& p) {
  return p.id ? static_cast<uint32_t>(1 + (p.id - 1) % 0xffffffffu) : 0;
}

// Component header: size (including this header and the count), type, count, drop rates.
std::string ComponentStart(Component c, uint32_t count, uint16_t drop_rate) {
  std::string out;
  PutU32(&out, 0);  // size, patched when the component is complete
  PutU32(&out, ComponentType(c));
  PutU32(&out, count);
  PutU16(&out, drop_rate);
  PutU16(&out, 0);  // out-of-sync rate: frame sets are assembled by frame number
  return out;
}

void Finish(std::string* component, std::string* packet_body) {
  const uint32_t size = static_cast<uint32_t>(component->size());
  for (int i = 0; i < 4; ++i) (*component)[i] = static_cast<char>((size >> (8 * i)) & 0xff);
  *packet_body += *component;
}

std::string Labelled3d(const pipeline::LiveFrame& frame, const RtNames& names, bool residual, uint16_t drop) {
  std::vector<const pipeline::LivePoint*> by_label(names.label_count(), nullptr);
  for (const pipeline::LivePoint& p : frame.points) {
    const int label = names.LabelOf(p);
    if (label >= 0 && static_cast<size_t>(label) < by_label.size()) by_label[static_cast<size_t>(label)] = &p;
  }
  std::string out = ComponentStart(residual ? k3dRes : k3d, static_cast<uint32_t>(by_label.size()), drop);
  for (const pipeline::LivePoint* p : by_label) {
    if (p) {
      PutVector(&out, p->position);
    } else {
      PutMissing(&out), PutMissing(&out), PutMissing(&out);
    }
    if (residual) {
      if (p) PutF32(&out, static_cast<float>(p->rms_px));
      else PutMissing(&out);
    }
  }
  return out;
}

std::string Unlabelled3d(const pipeline::LiveFrame& frame, bool residual, uint16_t drop) {
  std::string out = ComponentStart(residual ? k3dNoLabelsRes : k3dNoLabels,
                                   static_cast<uint32_t>(frame.points.size()), drop);
  for (const pipeline::LivePoint& p : frame.points) {
    PutVector(&out, p.position);
    PutU32(&out, PointId(p));
    if (residual) PutF32(&out, static_cast<float>(p.rms_px));
  }
  return out;
}

std::string SixD(const pipeline::LiveFrame& frame, const RtNames& names, Component c, uint16_t drop) {
  const bool euler = c == k6dEuler || c == k6dEulerRes;
  const bool residual = c == k6dRes || c == k6dEulerRes;
  std::string out = ComponentStart(c, static_cast<uint32_t>(names.bodies().size()), drop);
  for (const auto& [id, name] : names.bodies()) {
    const auto it = std::find_if(frame.bodies.begin(), frame.bodies.end(),
                                 [id = id](const pipeline::LiveBody& b) { return b.id == id; });
    const bool tracked = it != frame.bodies.end() && it->tracked;
    const int values = 3 + (euler ? 3 : 9) + (residual ? 1 : 0);
    if (!tracked) {
      for (int i = 0; i < values; ++i) PutMissing(&out);
      continue;
    }
    PutVector(&out, it->position);
    const Eigen::Matrix3d r = it->orientation.normalized().toRotationMatrix();
    if (euler) {
      PutVector(&out, EulerDegrees(r));
    } else {
      for (int col = 0; col < 3; ++col)
        for (int row = 0; row < 3; ++row) PutF32(&out, static_cast<float>(r(row, col)));
    }
    if (residual) PutF32(&out, static_cast<float>(it->mean_error_mm));
  }
  return out;
}

}  // namespace

void RtNames::Update(const pipeline::LiveFrame& frame) {
  if (frame.label_names && !set_names_) set_names_ = frame.label_names;
  for (const pipeline::LivePoint& p : frame.points) {
    if (p.provisional() || p.id == 0 || index_of_track_.count(p.id) || tracks_.size() >= kMaxLabels) continue;
    index_of_track_[p.id] = static_cast<int>(tracks_.size());
    tracks_.push_back(p.id);
  }
  for (const pipeline::LiveBody& b : frame.bodies)
    if (!bodies_.count(b.id) && bodies_.size() < kMaxBodies) bodies_[b.id] = b.name;
}

int RtNames::LabelOf(const pipeline::LivePoint& point) const {
  if (set_names_) return point.label;
  if (point.provisional()) return -1;
  const auto it = index_of_track_.find(point.id);
  return it == index_of_track_.end() ? -1 : it->second;
}

std::string RtNames::label_name(size_t label) const {
  if (set_names_) return label < set_names_->size() ? (*set_names_)[label] : std::string();
  return label < tracks_.size() ? TrackName(tracks_[label]) : std::string();
}

std::string RtNames::TrackName(uint64_t id) { return "T" + std::to_string(id); }

Eigen::Vector3d EulerDegrees(const Eigen::Matrix3d& r) {
  const double pitch = std::asin(std::clamp(r(0, 2), -1.0, 1.0));
  double roll = 0.0, yaw = 0.0;
  if (std::abs(r(0, 2)) < 1.0 - 1e-9) {
    roll = std::atan2(-r(1, 2), r(2, 2));
    yaw = std::atan2(-r(0, 1), r(0, 0));
  } else {
    // Gimbal lock: roll and yaw turn about the same axis; all of it is given to roll.
    roll = std::atan2(r(2, 1), r(1, 1));
  }
  constexpr double kDeg = 180.0 / 3.14159265358979323846;
  return {roll * kDeg, pitch * kDeg, yaw * kDeg};
}

std::string EncodeDataPacket(const pipeline::LiveFrame& frame, uint32_t components, const RtNames& names,
                             int expected_cameras) {
  uint16_t drop = 0;
  if (expected_cameras > 0 && frame.cameras < expected_cameras)
    drop = static_cast<uint16_t>((expected_cameras - frame.cameras) * 1000 / expected_cameras);
  std::string body;
  PutU64(&body, frame.trigger_time_ns / 1000);
  PutU32(&body, static_cast<uint32_t>(frame.frame_number));
  uint32_t count = 0;
  for (uint32_t bit = 1; bit <= kAllComponents; bit <<= 1)
    if (components & bit) ++count;
  PutU32(&body, count);
  // Ascending protocol type order: 3D (1), no labels (2), 6D (5), Euler (6), then the residual
  // variants (9-12); the bit order follows the type order.
  for (uint32_t bit = 1; bit <= kAllComponents; bit <<= 1) {
    if (!(components & bit)) continue;
    const Component c = static_cast<Component>(bit);
    std::string component;
    switch (c) {
      case k3d: component = Labelled3d(frame, names, false, drop); break;
      case k3dRes: component = Labelled3d(frame, names, true, drop); break;
      case k3dNoLabels: component = Unlabelled3d(frame, false, drop); break;
      case k3dNoLabelsRes: component = Unlabelled3d(frame, true, drop); break;
      case k6d: case k6dRes: case k6dEuler: case k6dEulerRes: component = SixD(frame, names, c, drop); break;
    }
    Finish(&component, &body);
  }
  return MakePacket(PacketType::kData, body);
}

}  // namespace mocap::stream::qtm

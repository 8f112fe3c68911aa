// NatNet model definitions and frames (see natnet_frame.h).
#include "stream/natnet/natnet_frame.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace mocap::stream::natnet {
namespace {

constexpr double kMetresPerMm = 1e-3;
constexpr int32_t kDatasetMarkerSet = 0;
constexpr int32_t kDatasetRigidBody = 1;
constexpr int32_t kDatasetSkeleton = 2;
constexpr int16_t kRigidBodyTracked = 0x01;
constexpr int16_t kMarkerPointCloudSolved = 0x02;
constexpr int16_t kMarkerHasModel = 0x08;
constexpr int16_t kMarkerUnlabeled = 0x10;
// Every point costs at most this much (a labelled-marker entry and a legacy other-marker entry).
constexpr size_t kBytesPerPoint = 26 + 12;

bool SizesSections(const Version& v) { return v.major > 4 || (v.major == 4 && v.minor >= 1); }

std::string MarkerName(size_t i) { return "Marker" + std::to_string(i + 1); }

void Vec(Writer& w, const Eigen::Vector3d& mm) {
  w.F32(static_cast<float>(mm.x() * kMetresPerMm));
  w.F32(static_cast<float>(mm.y() * kMetresPerMm));
  w.F32(static_cast<float>(mm.z() * kMetresPerMm));
}

void NaNs(Writer& w) {
  for (int i = 0; i < 3; ++i) w.F32(std::numeric_limits<float>::quiet_NaN());
}

// A section: its count, then (4.1) the byte size of what follows, patched when it ends.
class Section {
 public:
  Section(Writer& w, const Version& v, int32_t count) : w_(w), sized_(SizesSections(v)) {
    w.I32(count);
    if (sized_) at_ = w.Slot();
  }
  ~Section() {
    if (sized_) w_.PatchI32(at_, static_cast<int32_t>(w_.size() - at_ - 4));
  }

 private:
  Writer& w_;
  bool sized_;
  size_t at_ = 0;
};

void MarkerSetDescription(Writer& w, const std::string& name, const std::vector<std::string>& markers) {
  w.Str(name);
  w.I32(static_cast<int32_t>(markers.size()));
  for (const std::string& m : markers) w.Str(m);
}

void RigidBodyDescription(Writer& w, const Version& v, const RigidBodyDefinition& body, int32_t id) {
  w.Str(body.name);
  w.I32(id);
  w.I32(-1);  // parent: none
  for (int i = 0; i < 3; ++i) w.F32(0.0f);
  w.I32(static_cast<int32_t>(body.markers.size()));
  for (const Eigen::Vector3d& m : body.markers) Vec(w, m - body.pivot);
  for (size_t i = 0; i < body.markers.size(); ++i) w.I32(0);  // active labels: passive markers
  if (v.major >= 4)
    for (size_t i = 0; i < body.markers.size(); ++i) w.Str(MarkerName(i));
}

void SkeletonDescription(Writer& w, const pipeline::LiveSkeletonModel& skeleton, int32_t id) {
  w.Str(skeleton.name);
  w.I32(id);
  w.I32(static_cast<int32_t>(skeleton.bones.size()));
  for (size_t b = 0; b < skeleton.bones.size(); ++b) {
    w.Str(skeleton.bones[b]);
    w.I32(static_cast<int32_t>(b + 1));
    w.I32(skeleton.parents[b] + 1);  // 0: the root
    Vec(w, b < skeleton.offsets.size() ? skeleton.offsets[b] : Eigen::Vector3d::Zero());
    w.I32(0);  // markers: none (3.0 and later describe them here)
  }
}

// A dataset of the model definitions: type, (4.1) its byte size, the description.
template <typename Describe>
void Dataset(Writer& w, const Version& v, int32_t type, Describe&& describe) {
  w.I32(type);
  size_t at = 0;
  if (SizesSections(v)) at = w.Slot();
  describe();
  if (SizesSections(v)) w.PatchI32(at, static_cast<int32_t>(w.size() - at - 4));
}

const pipeline::LivePoint* NamedPoint(const pipeline::LiveFrame& frame, int label) {
  for (const pipeline::LivePoint& p : frame.points)
    if (p.label == label) return &p;
  return nullptr;
}

std::string Encode(const pipeline::LiveFrame& frame, const Model& model, const Version& v, const FrameStamps& stamps,
                   size_t max_points) {
  Writer w(kFrameOfData);
  w.I32(static_cast<int32_t>(static_cast<uint32_t>(frame.frame_number)));
  const bool labels = !model.label_names.empty();
  const size_t points = std::min(frame.points.size(), max_points);

  {  // markersets: each body's markers, then the marker set's names
    Section s(w, v, static_cast<int32_t>(model.bodies.size() + (labels ? 1 : 0)));
    for (size_t b = 0; b < model.bodies.size(); ++b) {
      const RigidBodyDefinition& def = model.bodies[b];
      w.Str(def.name);
      w.I32(static_cast<int32_t>(def.markers.size()));
      const pipeline::LiveBody* pose = b < frame.bodies.size() ? &frame.bodies[b] : nullptr;
      const bool placed = pose && (pose->tracked || pose->predicted);
      for (const Eigen::Vector3d& m : def.markers) {
        if (placed)
          Vec(w, pose->position + pose->orientation * (m - def.pivot));
        else
          NaNs(w);
      }
    }
    if (labels) {
      w.Str("all");
      w.I32(static_cast<int32_t>(model.label_names.size()));
      for (size_t l = 0; l < model.label_names.size(); ++l) {
        const pipeline::LivePoint* p = NamedPoint(frame, static_cast<int>(l));
        if (p)
          Vec(w, p->position);
        else
          NaNs(w);
      }
    }
  }
  {  // legacy other markers: points without a confirmed track
    int32_t others = 0;
    for (size_t i = 0; i < points; ++i) others += frame.points[i].marker < 0;
    Section s(w, v, others);
    for (size_t i = 0; i < points; ++i)
      if (frame.points[i].marker < 0) Vec(w, frame.points[i].position);
  }
  {  // rigid bodies
    Section s(w, v, static_cast<int32_t>(frame.bodies.size()));
    for (const pipeline::LiveBody& b : frame.bodies) {
      w.I32(static_cast<int32_t>(b.id));
      Vec(w, b.position);
      const Eigen::Quaterniond q = b.orientation.normalized();
      w.F32(static_cast<float>(q.x()));
      w.F32(static_cast<float>(q.y()));
      w.F32(static_cast<float>(q.z()));
      w.F32(static_cast<float>(q.w()));
      w.F32(static_cast<float>(b.mean_error_mm * kMetresPerMm));
      w.I16(b.tracked ? kRigidBodyTracked : 0);
    }
  }
  {  // skeletons: each model skeleton, solved or not
    Section s(w, v, static_cast<int32_t>(model.skeletons.size()));
    for (size_t k = 0; k < model.skeletons.size(); ++k) {
      const int32_t id = static_cast<int32_t>(model.bodies.size() + 1 + k);
      const pipeline::LiveSkeletonModel& bones = *model.skeletons[k];
      const pipeline::LiveSkeleton* live = k < frame.skeletons.size() ? &frame.skeletons[k] : nullptr;
      const bool solved = live && live->solved && live->bones.size() == bones.bones.size();
      w.I32(id);
      w.I32(static_cast<int32_t>(bones.bones.size()));
      for (size_t b = 0; b < bones.bones.size(); ++b) {
        w.I32(static_cast<int32_t>((static_cast<uint32_t>(id) << 16) | static_cast<uint32_t>(b + 1)));
        if (solved) {
          Vec(w, live->bones[b].position);
          const Eigen::Quaterniond q = live->bones[b].orientation.normalized();
          w.F32(static_cast<float>(q.x()));
          w.F32(static_cast<float>(q.y()));
          w.F32(static_cast<float>(q.z()));
          w.F32(static_cast<float>(q.w()));
          w.F32(static_cast<float>(live->rms_mm * kMetresPerMm));
        } else {
          NaNs(w);
          for (int i = 0; i < 4; ++i) w.F32(std::numeric_limits<float>::quiet_NaN());
          w.F32(0.0f);
        }
        w.I16(solved ? kRigidBodyTracked : 0);
      }
    }
  }
  if (SizesSections(v)) { Section s(w, v, 0); }  // assets
  {  // labelled markers: every point
    Section s(w, v, static_cast<int32_t>(points));
    for (size_t i = 0; i < points; ++i) {
      const pipeline::LivePoint& p = frame.points[i];
      w.I32(p.id ? static_cast<int32_t>(1 + (p.id - 1) % 0x7fffffffu) : 0);
      Vec(w, p.position);
      w.F32(0.0f);  // size: not measured
      int16_t params = kMarkerPointCloudSolved;
      if (p.marker < 0) params |= kMarkerUnlabeled;
      if (p.label >= 0) params |= kMarkerHasModel;
      w.I16(params);
      w.F32(0.0f);  // residual: not in metres here
    }
  }
  { Section s(w, v, 0); }  // force plates
  { Section s(w, v, 0); }  // devices
  w.U32(0);  // timecode
  w.U32(0);  // timecode subframe
  w.F64(model.rate_hz > 0 ? static_cast<double>(frame.frame_number) / model.rate_hz : 0.0);
  w.U64(frame.trigger_time_ns);
  w.U64(frame.last_receive_ns);
  w.U64(stamps.transmit_ns);
  if (v.major >= 4) {
    w.U32(0);  // precision timestamp: seconds
    w.U32(0);  // and fraction
  }
  w.I16(0);  // frame params
  w.I32(0);  // end of data
  return w.Finish();
}

}  // namespace

std::string EncodeModelDef(const Model& model, const Version& v) {
  Writer w(kModelDef);
  const bool labels = !model.label_names.empty();
  w.I32(static_cast<int32_t>(2 * model.bodies.size() + (labels ? 1 : 0) + model.skeletons.size()));
  for (const RigidBodyDefinition& body : model.bodies)
    Dataset(w, v, kDatasetMarkerSet, [&] {
      std::vector<std::string> names;
      for (size_t i = 0; i < body.markers.size(); ++i) names.push_back(MarkerName(i));
      MarkerSetDescription(w, body.name, names);
    });
  if (labels) Dataset(w, v, kDatasetMarkerSet, [&] { MarkerSetDescription(w, "all", model.label_names); });
  for (size_t b = 0; b < model.bodies.size(); ++b)
    Dataset(w, v, kDatasetRigidBody, [&] { RigidBodyDescription(w, v, model.bodies[b], static_cast<int32_t>(b + 1)); });
  for (size_t k = 0; k < model.skeletons.size(); ++k)
    Dataset(w, v, kDatasetSkeleton, [&] {
      SkeletonDescription(w, *model.skeletons[k], static_cast<int32_t>(model.bodies.size() + 1 + k));
    });
  return w.Finish();
}

std::string EncodeFrame(const pipeline::LiveFrame& frame, const Model& model, const Version& version,
                        const FrameStamps& stamps, uint64_t* points_dropped) {
  std::string packet = Encode(frame, model, version, stamps, frame.points.size());
  if (packet.size() <= kMaxPacket) return packet;
  const std::string bare = Encode(frame, model, version, stamps, 0);
  const size_t fit = bare.size() < kMaxPacket ? (kMaxPacket - bare.size()) / kBytesPerPoint : 0;
  if (points_dropped) *points_dropped += frame.points.size() - std::min(fit, frame.points.size());
  return Encode(frame, model, version, stamps, fit);
}

}  // namespace mocap::stream::natnet

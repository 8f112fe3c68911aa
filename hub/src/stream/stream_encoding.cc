// StreamFrame encoding and request decoding (see stream_encoding.h).
#include "stream/stream_encoding.h"

#include <sstream>
#include <stdexcept>

#include "mocap_stream.pb.h"

namespace mocap::stream {
namespace {

void FillPoint(const pipeline::LivePoint& in, const std::vector<std::string>* names, v1::Point* out) {
  out->set_x(static_cast<float>(in.position.x()));
  out->set_y(static_cast<float>(in.position.y()));
  out->set_z(static_cast<float>(in.position.z()));
  out->set_residual_px(static_cast<float>(in.rms_px));
  out->set_views(static_cast<uint32_t>(in.views));
  if (in.marker >= 0) out->set_marker(in.marker + 1);
  out->set_id(in.id);
  if (in.marker < 0) out->set_provisional_track(in.id);
  if (names != nullptr && in.label >= 0 && static_cast<size_t>(in.label) < names->size())
    out->set_label((*names)[static_cast<size_t>(in.label)].substr(0, 63));  // the field's nanopb limit
}

void FillBody(const pipeline::LiveBody& in, v1::RigidBody* out) {
  out->set_id(in.id);
  out->set_name(in.name);
  out->set_tracked(in.tracked);
  out->set_predicted(in.predicted);
  out->set_markers(static_cast<uint32_t>(in.markers));
  if (!in.tracked && !in.predicted) return;
  out->set_x(static_cast<float>(in.position.x()));
  out->set_y(static_cast<float>(in.position.y()));
  out->set_z(static_cast<float>(in.position.z()));
  out->set_qx(static_cast<float>(in.orientation.x()));
  out->set_qy(static_cast<float>(in.orientation.y()));
  out->set_qz(static_cast<float>(in.orientation.z()));
  out->set_qw(static_cast<float>(in.orientation.w()));
  out->set_mean_error_mm(static_cast<float>(in.mean_error_mm));
}

void FillSkeleton(const pipeline::LiveSkeleton& in, v1::Skeleton* out) {
  if (in.model) out->set_name(in.model->name.substr(0, 63));
  out->set_solved(in.solved);
  out->set_state(in.state);
  out->set_markers(static_cast<uint32_t>(in.markers));
  out->set_rms_mm(static_cast<float>(in.rms_mm));
  out->set_max_mm(static_cast<float>(in.max_mm));
  for (size_t b = 0; in.model && b < in.bones.size() && b < in.model->bones.size(); ++b) {
    v1::Bone* bone = out->add_bones();
    bone->set_name(in.model->bones[b].substr(0, 63));  // the field's nanopb limit
    bone->set_parent(in.model->parents[b]);
    bone->set_x(static_cast<float>(in.bones[b].position.x()));
    bone->set_y(static_cast<float>(in.bones[b].position.y()));
    bone->set_z(static_cast<float>(in.bones[b].position.z()));
    bone->set_qx(static_cast<float>(in.bones[b].orientation.x()));
    bone->set_qy(static_cast<float>(in.bones[b].orientation.y()));
    bone->set_qz(static_cast<float>(in.bones[b].orientation.z()));
    bone->set_qw(static_cast<float>(in.bones[b].orientation.w()));
  }
}

}  // namespace

EncodedFrame EncodeStreamFrame(const pipeline::LiveFrame& frame, uint32_t parts, size_t max_bytes) {
  v1::StreamFrame out;
  out.set_frame_number(frame.frame_number);
  out.set_trigger_time_ns(frame.trigger_time_ns);
  out.set_publish_time_ns(frame.publish_ns);
  out.set_cameras(static_cast<uint32_t>(frame.cameras));
  out.set_parts(parts & kAllParts);
  if (parts & kPartBodies)
    for (const pipeline::LiveBody& body : frame.bodies) FillBody(body, out.add_bodies());
  if (parts & kPartBones)
    for (const pipeline::LiveSkeleton& skeleton : frame.skeletons) FillSkeleton(skeleton, out.add_skeletons());
  if (parts & kPartPoints) {
    // Points are added while they fit: each one's size is known before it is added, so the
    // message never grows past the limit (a varint length prefix and tag: at most 3 bytes more).
    size_t size = out.ByteSizeLong() + 8;  // + room for points_dropped
    for (const pipeline::LivePoint& point : frame.points) {
      v1::Point p;
      FillPoint(point, (parts & kPartLabels) && frame.label_names ? frame.label_names.get() : nullptr, &p);
      const size_t cost = p.ByteSizeLong() + 3;
      if (size + cost > max_bytes) {
        out.set_points_dropped(out.points_dropped() + 1);
        continue;
      }
      size += cost;
      *out.add_points() = std::move(p);
    }
  }
  return {out.SerializeAsString(), out.points_dropped()};
}

StreamRequest DecodeStreamRequest(const uint8_t* data, size_t size) {
  StreamRequest result;
  if (size > kMaxStreamRequest) {
    result.reason = "request of " + std::to_string(size) + " bytes (at most " + std::to_string(kMaxStreamRequest) + ")";
    return result;
  }
  v1::StreamRequest request;
  if (!request.ParseFromArray(data, static_cast<int>(size))) {
    result.reason = "not a StreamRequest";
    return result;
  }
  if (request.version() != kStreamVersion) {
    result.reason = "stream version " + std::to_string(request.version()) + " (this hub speaks " +
                    std::to_string(kStreamVersion) + ")";
    return result;
  }
  switch (request.body_case()) {
    case v1::StreamRequest::kSubscribe: {
      const uint32_t parts = request.subscribe().parts();
      if (parts & ~kAllParts) {
        result.reason = "unknown part bits " + std::to_string(parts & ~kAllParts);
        return result;
      }
      result.subscribe = true;
      result.parts = parts ? parts : kDefaultParts;
      result.cookie = request.subscribe().cookie();
      break;
    }
    case v1::StreamRequest::kUnsubscribe:
      result.cookie = request.unsubscribe().cookie();
      break;
    default:
      result.reason = "request without subscribe or unsubscribe";
      return result;
  }
  if (result.cookie.size() > kMaxStreamCookie) {
    result.reason = "cookie of " + std::to_string(result.cookie.size()) + " bytes (at most " +
                    std::to_string(kMaxStreamCookie) + ")";
    result.cookie.clear();
    return result;
  }
  result.ok = true;
  return result;
}

std::string EncodeSubscribe(uint32_t parts, const std::string& cookie) {
  v1::StreamRequest request;
  request.set_version(kStreamVersion);
  request.mutable_subscribe()->set_parts(parts);
  request.mutable_subscribe()->set_cookie(cookie);
  if (cookie.empty()) {
    const size_t bare = request.ByteSizeLong();
    // The padding field's own tag and length take two bytes.
    if (bare + 2 < kMinFirstRequest) request.mutable_subscribe()->set_padding(std::string(kMinFirstRequest - bare - 2, '\0'));
  }
  return request.SerializeAsString();
}

std::string EncodeUnsubscribe(const std::string& cookie) {
  v1::StreamRequest request;
  request.set_version(kStreamVersion);
  request.mutable_unsubscribe()->set_cookie(cookie);
  return request.SerializeAsString();
}

std::string EncodeChallenge(const std::string& cookie) {
  v1::StreamFrame frame;
  frame.set_subscribe_cookie(cookie);
  return frame.SerializeAsString();
}

uint32_t ParseParts(const std::string& text) {
  uint32_t parts = 0;
  std::stringstream in(text);
  for (std::string part; std::getline(in, part, ',');) {
    if (part == "points") parts |= kPartPoints;
    else if (part == "bodies") parts |= kPartBodies;
    else if (part == "labels") parts |= kPartLabels;
    else if (part == "bones") parts |= kPartBones;
    else throw std::invalid_argument("unknown stream part '" + part + "' (points, bodies, labels, bones)");
  }
  if (!parts) throw std::invalid_argument("no stream parts given (points, bodies, labels, bones)");
  return parts;
}

}  // namespace mocap::stream

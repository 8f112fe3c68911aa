// Protocol-v1 datagram rules: every check the hub applies before trusting a datagram.
#include "wire/packet.h"

#include <cmath>
#include <mutex>
#include <stdexcept>

#include <google/protobuf/stubs/logging.h>

#include "wire/limits.h"

namespace mocap::wire {
namespace {

std::string ValidateMarkerFrame(const v1::MarkerFrame& f) {
  if (f.node_id() == 0) return "marker frame: node_id 0";
  if (f.width() == 0 || f.height() == 0 || f.width() > kMaxImageSide || f.height() > kMaxImageSide)
    return "marker frame: image size out of range";
  if (f.marker_total() > kMaxMarkersPerFrame) return "marker frame: too many markers";
  const uint32_t expected_chunks =
      f.marker_total() == 0 ? 1 : (f.marker_total() + kMarkersPerChunk - 1) / kMarkersPerChunk;
  if (f.chunk_count() != expected_chunks) return "marker frame: chunk_count does not match marker_total";
  if (f.chunk_index() >= f.chunk_count()) return "marker frame: chunk_index out of range";
  if (f.first_marker() != f.chunk_index() * kMarkersPerChunk)
    return "marker frame: first_marker does not match chunk_index";
  const uint32_t remaining = f.marker_total() - f.first_marker();
  const uint32_t expected_here = remaining < kMarkersPerChunk ? remaining : kMarkersPerChunk;
  if (static_cast<uint32_t>(f.markers_size()) != expected_here)
    return "marker frame: wrong number of markers in chunk";
  if (f.flags() & ~kFrameFlagsMask) return "marker frame: unknown frame flags";
  const uint64_t max_x = uint64_t{f.width()} * 256u, max_y = uint64_t{f.height()} * 256u;
  for (const auto& m : f.markers()) {
    if (m.x_q8() >= max_x || m.y_q8() >= max_y) return "marker: centroid outside the image";
    if (m.area() == 0 || m.area() > kMaxBlobArea) return "marker: area out of range";
    if (m.peak() > kMaxBrightness || m.mean() > m.peak()) return "marker: brightness out of range";
    if (m.flags() & ~kMarkerFlagsMask) return "marker: unknown marker flags";
  }
  return {};
}

std::string ValidateNodeStatus(const v1::NodeStatus& s) {
  if (s.node_id() == 0) return "node status: node_id 0";
  if (s.firmware_version().size() > kMaxFirmwareVersionChars) return "node status: version too long";
  if (!v1::NodeState_IsValid(s.state())) return "node status: unknown state";
  return {};
}

std::string ValidateControl(const v1::Control& c) {
  switch (c.command_case()) {
    case v1::Control::COMMAND_NOT_SET:
      return "control: no command";
    case v1::Control::kStart:
      if (c.start().rate_millihz() == 0) return "control: start with rate 0";
      return {};
    case v1::Control::kSetThreshold:
      if (!c.set_threshold().automatic() && c.set_threshold().value() > kMaxBrightness)
        return "control: threshold out of range";
      return {};
    case v1::Control::kSetMask: {
      const auto& m = c.set_mask();
      if (static_cast<uint32_t>(m.rects_size()) > kMaxMaskRects) return "control: too many mask rects";
      if (m.bits().size() > kMaxMaskBitsBytes) return "control: mask chunk too large";
      if (!m.bits().empty()) {
        if (m.cell_px() == 0 || m.cells_x() == 0 || m.cells_y() == 0) return "control: mask image without size";
        if (m.chunk_count() == 0 || m.chunk_index() >= m.chunk_count()) return "control: mask chunk out of range";
        const uint64_t total_bits = uint64_t{m.cells_x()} * m.cells_y();
        if (m.bit_offset() % 8 != 0 || m.bit_offset() + 8ull * m.bits().size() > total_bits + 7)
          return "control: mask bits outside the mask image";
      }
      for (const auto& r : m.rects())
        if (r.width() == 0 || r.height() == 0 || r.x() + uint64_t{r.width()} > kMaxImageSide + 1 ||
            r.y() + uint64_t{r.height()} > kMaxImageSide + 1)
          return "control: mask rect out of range";
      return {};
    }
    case v1::Control::kPreviewRequest: {
      const uint32_t d = c.preview_request().downscale();
      if (d != 1 && d != 2 && d != 4 && d != 8) return "control: preview downscale must be 1, 2, 4 or 8";
      if (!v1::PreviewMode_IsValid(c.preview_request().mode())) return "control: unknown preview mode";
      return {};
    }
    case v1::Control::kSetPicture: {
      const v1::SetPicture& p = c.set_picture();
      if (!p.set_brightness() && !p.set_contrast()) return "control: picture command changes nothing";
      if ((p.set_brightness() && p.brightness_pct() > 100) || (p.set_contrast() && p.contrast_pct() > 100))
        return "control: picture control outside 0..100 %";
      return {};
    }
    case v1::Control::kStop:
    case v1::Control::kSetExposure:
    case v1::Control::kIdentify:
      return {};
  }
  return "control: unknown command";
}

std::string ValidateControlAck(const v1::ControlAck& a) {
  if (a.node_id() == 0) return "control ack: node_id 0";
  if (!v1::ControlResult_IsValid(a.result())) return "control ack: unknown result";
  if (a.reason().size() > kMaxAckReasonBytes) return "control ack: reason too long";
  if (a.result() == v1::CONTROL_RESULT_APPLIED && !a.reason().empty())
    return "control ack: applied with a reason";
  if (a.result() == v1::CONTROL_RESULT_REJECTED && a.reason().empty())
    return "control ack: rejected without a reason";
  return {};
}

std::string ValidatePreviewChunk(const v1::PreviewChunk& p) {
  if (p.node_id() == 0) return "preview: node_id 0";
  if (!v1::PreviewMode_IsValid(p.mode())) return "preview: unknown mode";
  if (p.width() == 0 || p.height() == 0 || p.width() > kMaxImageSide || p.height() > kMaxImageSide)
    return "preview: image size out of range";
  if (p.chunk_count() == 0 || p.chunk_index() >= p.chunk_count()) return "preview: chunk out of range";
  if (p.data().size() > kMaxPreviewChunkBytes) return "preview: chunk too large";
  if (p.offset() + uint64_t{p.data().size()} > uint64_t{p.width()} * p.height())
    return "preview: data outside the image";
  return {};
}

}  // namespace

std::string Validate(const v1::Packet& packet) {
  if (packet.version() != kProtocolVersion)
    return "unsupported protocol version " + std::to_string(packet.version());
  switch (packet.body_case()) {
    case v1::Packet::kMarkerFrame: return ValidateMarkerFrame(packet.marker_frame());
    case v1::Packet::kNodeStatus: return ValidateNodeStatus(packet.node_status());
    case v1::Packet::kControl: return ValidateControl(packet.control());
    case v1::Packet::kPreviewChunk: return ValidatePreviewChunk(packet.preview_chunk());
    case v1::Packet::kHubAnnounce:
      if (packet.hub_announce().port() == 0 || packet.hub_announce().port() > 65535)
        return "hub announce: port out of range";
      return {};
    case v1::Packet::kControlAck: return ValidateControlAck(packet.control_ack());
    case v1::Packet::BODY_NOT_SET: return "packet without body";
  }
  return "unknown packet body";
}

DecodeResult Decode(const uint8_t* data, size_t size) {
  // libprotobuf logs every invalid UTF-8 string it refuses; outside input is refused with a
  // reason here instead, so its log would only flood the hub's stderr.
  static std::once_flag quiet;
  std::call_once(quiet, [] { google::protobuf::SetLogHandler(nullptr); });
  DecodeResult result;
  if (size == 0) {
    result.reason = "empty datagram";
    return result;
  }
  if (size > kMaxPacketBytes) {
    result.reason = "packet larger than 1352 bytes (1400 with its envelope)";
    return result;
  }
  if (!result.packet.ParseFromArray(data, static_cast<int>(size))) {
    result.reason = "not a protocol buffer packet";
    return result;
  }
  result.reason = Validate(result.packet);
  result.ok = result.reason.empty();
  return result;
}

std::vector<uint8_t> Encode(const v1::Packet& packet) {
  const std::string problem = Validate(packet);
  if (!problem.empty()) throw std::invalid_argument("refusing to encode: " + problem);
  const size_t size = packet.ByteSizeLong();
  if (size > kMaxPacketBytes) throw std::invalid_argument("refusing to encode: packet over 1352 bytes");
  std::vector<uint8_t> bytes(size);
  if (!packet.SerializeToArray(bytes.data(), static_cast<int>(size)))
    throw std::invalid_argument("refusing to encode: serialization failed");
  return bytes;
}

std::vector<uint8_t> EncodeHubAnnounce(uint16_t port, uint64_t epoch_ns, double rate_hz) {
  v1::Packet p;
  p.set_version(kProtocolVersion);
  v1::HubAnnounce* a = p.mutable_hub_announce();
  a->set_port(port);
  a->set_epoch_ns(epoch_ns);
  a->set_rate_millihz(static_cast<uint32_t>(rate_hz * 1000.0 + 0.5));
  return Encode(p);
}

uint32_t ToSubpixel(double px) {
  if (!(px > 0.0)) return 0;
  const double q = std::round(px * kSubpixelScale);
  return q >= 4294967295.0 ? 4294967295u : static_cast<uint32_t>(q);
}

double FromSubpixel(uint32_t q) { return q / kSubpixelScale; }

}  // namespace mocap::wire

// Datagram ingest shared by record and serve (see frame_ingest.h).
#include "ingest/frame_ingest.h"

#include "ingest/frame_codec.h"

namespace mocap {

uint32_t SenderNodeId(const v1::Packet& packet) {
  if (packet.has_marker_frame()) return packet.marker_frame().node_id();
  if (packet.has_node_status()) return packet.node_status().node_id();
  if (packet.has_preview_chunk()) return packet.preview_chunk().node_id();
  if (packet.has_control_ack()) return packet.control_ack().node_id();
  return 0;
}

FrameIngest::FrameIngest(const std::vector<uint32_t>& cameras, const FrameSetAssemblerOptions& assembly,
                         WireAuthOptions auth, ImageSizes image_sizes)
    : auth_(std::move(auth)), image_sizes_(std::move(image_sizes)), assembler_(assembly, cameras) {
  for (uint32_t id : cameras) stats_.nodes[id];
}

const wire::DecodeResult& FrameIngest::Add(const Datagram& d, SessionWriter* session) {
  last_outcome_ = IngestOutcome::kAccepted;
  const WireOpened opened = auth_.Open(d.bytes.data(), d.bytes.size(), d.receive_time_ns, &d.from);
  if (!opened.ok) return RefuseUnauthentic(opened.reason, d);
  decoded_ = wire::Decode(opened.payload, opened.payload_size);
  if (!decoded_.ok) {
    last_outcome_ = IngestOutcome::kMalformed;
    if (stats_.malformed++ == 0) {
      stats_.first_malformed_reason = decoded_.reason;
      stats_.first_malformed_source = d.FromString();
    }
    return decoded_;
  }
  const uint32_t node = SenderNodeId(decoded_.packet);
  if (!auth_.insecure() && node != opened.node_id) {
    // Authentic, but a node may only speak for itself (and never send the hub's packet kinds).
    auth_.CountNodeMismatch(opened.node_id);
    return RefuseUnauthentic("node " + std::to_string(opened.node_id) + " sent a packet for node " +
                                 std::to_string(node),
                             d);
  }
  auto known = stats_.nodes.find(node);
  if (known == stats_.nodes.end()) {
    ++stats_.unknown_nodes[node];
    return decoded_;
  }
  NodeStats& ns = known->second;
  ++ns.datagrams;
  if (decoded_.packet.has_marker_frame()) {
    // Refused before the log, the chunk reassembly and the frame sets: what a forged or
    // mis-clocked frame number would disturb.
    const uint64_t number = decoded_.packet.marker_frame().frame_number();
    if (!assembler_.OnSessionClock(number, d.receive_time_ns)) {
      ++ns.off_clock_frames;
      ns.off_clock_s = assembler_.ClockOffsetS(number, d.receive_time_ns);
      last_outcome_ = IngestOutcome::kOffClock;
      return decoded_;
    }
  }
  if (session) session->AppendDatagram(opened.payload, opened.payload_size, d.receive_time_ns);
  if (decoded_.packet.has_node_status()) {
    ++ns.status_packets;
    ns.has_status = true;
    ns.last_status = decoded_.packet.node_status();
  } else if (decoded_.packet.has_marker_frame()) {
    AddMarkerFrame(decoded_.packet.marker_frame(), d.receive_time_ns, &ns);
  }
  return decoded_;
}

const wire::DecodeResult& FrameIngest::RefuseUnauthentic(const std::string& reason, const Datagram& d) {
  last_outcome_ = IngestOutcome::kUnauthentic;
  decoded_.ok = false;
  decoded_.reason = reason;
  decoded_.packet.Clear();
  if (stats_.unauthentic++ == 0) {
    stats_.first_unauthentic_reason = reason;
    stats_.first_unauthentic_source = d.FromString();
  }
  return decoded_;
}

void FrameIngest::AddMarkerFrame(const v1::MarkerFrame& chunk, uint64_t receive_time_ns, NodeStats* ns) {
  v1::MarkerFrame whole;
  switch (chunks_.Add(chunk, &whole)) {
    case wire::ChunkAssembler::Outcome::kDuplicate: ++ns->duplicate_chunks; return;
    case wire::ChunkAssembler::Outcome::kInconsistent: ++ns->inconsistent_chunks; return;
    case wire::ChunkAssembler::Outcome::kIncomplete:
    case wire::ChunkAssembler::Outcome::kOverflow: return;
    case wire::ChunkAssembler::Outcome::kComplete: break;
  }
  stats_.CountFrame(whole.node_id(), whole.frame_number());
  CameraFrame frame = FromMarkerFrame(whole, receive_time_ns);
  ns->width = frame.width;
  ns->height = frame.height;
  switch (image_sizes_.Apply(&frame)) {
    case ImageSizeVerdict::kRefused: ++ns->wrong_size_frames; return;
    case ImageSizeVerdict::kRescaled: ++ns->rescaled_frames; break;
    case ImageSizeVerdict::kSame: break;
  }
  if (!assembler_.Add(std::move(frame), receive_time_ns)) ++ns->late_frames;
}

std::vector<FrameSet> FrameIngest::Flush() {
  chunks_.DiscardBefore(~0ull);
  return assembler_.Flush();
}

}  // namespace mocap

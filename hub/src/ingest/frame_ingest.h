// What a live hub does with every datagram from the nodes, shared by `record` and `serve`:
// open its authenticated envelope (ingest/wire_auth.h: forged, replayed, stale or plain
// datagrams are counted and go no further), decode the packet inside by the wire rules
// (malformed input counted with its first reason), attribute it to a camera of the calibration
// (others counted per node id), refuse marker frames numbered off the session clock (counted per
// node), append its packet to the session's raw log as received (the envelope's payload: logs
// stay readable without keys) when a capture runs, reassemble marker-frame chunks and assemble the camera
// frames into frame sets under the deadline; a camera frame of another image size than the
// calibration's is rescaled or refused (image_size_check.h), the raw log keeping it as received.
// Bad input is counted, never fatal.
#pragma once

#include <cstdint>
#include <vector>

#include "ingest/frame_set_assembler.h"
#include "ingest/image_size_check.h"
#include "ingest/ingest_stats.h"
#include "ingest/session.h"
#include "ingest/udp_socket.h"
#include "ingest/wire_auth.h"
#include "wire/chunking.h"
#include "wire/packet.h"

namespace mocap {

// The node a valid packet speaks for (marker frame, status, preview chunk, control ack); 0 when
// it names none (e.g. a HubAnnounce).
uint32_t SenderNodeId(const v1::Packet& packet);

// What became of the last datagram given to FrameIngest::Add.
enum class IngestOutcome {
  kAccepted,     // decoded and attributed (or counted as an unknown node's)
  kMalformed,    // refused by the wire rules
  kUnauthentic,  // refused by the envelope: forged, replayed, stale, plain, or speaking for another node
  kOffClock,     // a marker frame numbered off the session clock: counted for its node, not used
};

class FrameIngest {
 public:
  // cameras: the node ids of the calibration; assembly.Check() must hold (std::invalid_argument);
  // auth: the keys (WireAuth's constructor throws for a bad keys directory); image_sizes: the
  // calibration's, so that frames of another size are rescaled or refused (image_size_check.h).
  FrameIngest(const std::vector<uint32_t>& cameras, const FrameSetAssemblerOptions& assembly,
              WireAuthOptions auth, ImageSizes image_sizes = {});

  // One received datagram. `session` (may be null: nothing is being captured) gets every valid
  // datagram of a known camera. Returns the decode result so the caller can route the other
  // packet kinds (status, acks, previews) without decoding twice.
  const wire::DecodeResult& Add(const Datagram& datagram, SessionWriter* session);
  // Frame sets complete or overdue at now_ns / everything still open.
  std::vector<FrameSet> Collect(uint64_t now_ns) { return assembler_.Collect(now_ns); }
  std::vector<FrameSet> Flush();

  bool IsCamera(uint32_t node_id) const { return stats_.nodes.count(node_id) != 0; }
  IngestOutcome last_outcome() const { return last_outcome_; }
  WireAuth& auth() { return auth_; }
  const WireAuth& auth() const { return auth_; }
  const IngestStats& stats() const { return stats_; }
  const FrameSetAssembler& assembler() const { return assembler_; }

 private:
  void AddMarkerFrame(const v1::MarkerFrame& chunk, uint64_t receive_time_ns, NodeStats* node);
  const wire::DecodeResult& RefuseUnauthentic(const std::string& reason, const Datagram& d);

  WireAuth auth_;
  wire::DecodeResult decoded_;
  IngestOutcome last_outcome_ = IngestOutcome::kAccepted;
  wire::ChunkAssembler chunks_;
  ImageSizeCheck image_sizes_;
  FrameSetAssembler assembler_;
  IngestStats stats_;
};

}  // namespace mocap

// Per-node reception statistics of a live session: what arrived, what was lost or refused.
#pragma once

#include <cstdint>
#include <map>
#include <string>

#include "mocap.pb.h"

namespace mocap {

struct NodeStats {
  uint64_t datagrams = 0;
  uint64_t frames = 0;           // complete camera frames
  uint64_t dropped_frames = 0;   // gaps in the node's frame numbers
  uint64_t late_frames = 0;      // arrived after their frame set was handed out
  uint64_t off_clock_frames = 0; // marker-frame datagrams numbered off the session clock: refused
  double off_clock_s = 0.0;      // the last refused one: its trigger time minus its arrival, s
  uint64_t rescaled_frames = 0;  // image size differs from the calibration's, same aspect: rescaled
  uint64_t wrong_size_frames = 0;  // image size of another aspect ratio than the calibration's: refused
  uint32_t width = 0, height = 0;  // image size of the last complete frame
  uint64_t duplicate_chunks = 0;
  uint64_t inconsistent_chunks = 0;
  uint64_t status_packets = 0;
  bool has_last_frame = false;
  uint64_t last_frame_number = 0;
  bool has_status = false;
  v1::NodeStatus last_status;
};

struct IngestTotals {
  uint64_t frames = 0, dropped_frames = 0, late_frames = 0, off_clock_frames = 0;
  uint64_t rescaled_frames = 0, wrong_size_frames = 0;
};

struct IngestStats {
  std::map<uint32_t, NodeStats> nodes;      // nodes named in the calibration
  std::map<uint32_t, uint64_t> unknown_nodes;  // node id -> datagrams, not in the calibration
  uint64_t malformed = 0;
  std::string first_malformed_reason;
  std::string first_malformed_source;
  uint64_t unauthentic = 0;  // refused by the authenticated wire (ingest/wire_auth.h has the kinds)
  std::string first_unauthentic_reason;
  std::string first_unauthentic_source;

  // Records a complete frame from a known node, counting gaps in its numbering.
  void CountFrame(uint32_t node, uint64_t frame_number);
  // Summed over the calibration's nodes.
  IngestTotals Totals() const;
  // A human-readable table, one line per node, plus unknown nodes and malformed input.
  std::string Report() const;
};

}  // namespace mocap

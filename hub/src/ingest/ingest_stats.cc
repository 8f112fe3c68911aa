// Reception statistics bookkeeping and report (see ingest_stats.h).
#include "ingest/ingest_stats.h"

#include <sstream>

namespace mocap {

void IngestStats::CountFrame(uint32_t node, uint64_t frame_number) {
  NodeStats& s = nodes[node];
  if (s.has_last_frame && frame_number > s.last_frame_number + 1)
    s.dropped_frames += frame_number - s.last_frame_number - 1;
  if (!s.has_last_frame || frame_number > s.last_frame_number) s.last_frame_number = frame_number;
  s.has_last_frame = true;
  ++s.frames;
}

IngestTotals IngestStats::Totals() const {
  IngestTotals t;
  for (const auto& [id, s] : nodes) {
    t.frames += s.frames;
    t.dropped_frames += s.dropped_frames;
    t.late_frames += s.late_frames;
    t.off_clock_frames += s.off_clock_frames;
    t.rescaled_frames += s.rescaled_frames;
    t.wrong_size_frames += s.wrong_size_frames;
  }
  return t;
}

std::string IngestStats::Report() const {
  std::ostringstream out;
  out << "node  datagrams    frames  dropped  late  off-clock  dup-chunks  image  status\n";
  for (const auto& [id, s] : nodes) {
    out << "  " << id << "  " << s.datagrams << "  " << s.frames << "  " << s.dropped_frames << "  "
        << s.late_frames << "  " << s.off_clock_frames << "  " << s.duplicate_chunks + s.inconsistent_chunks << "  "
        << s.width << "x" << s.height;
    if (s.rescaled_frames) out << " (" << s.rescaled_frames << " rescaled)";
    if (s.wrong_size_frames) out << " (" << s.wrong_size_frames << " refused: wrong size)";
    out << "  ";
    if (s.has_status)
      out << "fps " << s.last_status.fps_milli() / 1000.0 << ", detect " << s.last_status.detect_time_us_mean()
          << " us, sync jitter " << s.last_status.sync().edge_jitter_ns() << " ns, missed edges "
          << s.last_status.sync().missed_edges() << ", camera reopens " << s.last_status.camera_reopens();
    else
      out << "no status received";
    out << "\n";
  }
  for (const auto& [id, count] : unknown_nodes)
    out << "unknown node " << id << " (not in the calibration): " << count << " datagrams ignored\n";
  if (malformed)
    out << malformed << " malformed datagrams dropped (first from " << first_malformed_source << ": "
        << first_malformed_reason << ")\n";
  if (unauthentic)
    out << unauthentic << " unauthentic datagrams refused (forged, replayed, stale or plain; first from "
        << first_unauthentic_source << ": " << first_unauthentic_reason << ")\n";
  return out.str();
}

}  // namespace mocap

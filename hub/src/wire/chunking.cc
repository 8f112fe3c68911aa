// Chunk split/reassembly of marker frames (see chunking.h for the rule).
#include "wire/chunking.h"

#include <algorithm>

#include "wire/limits.h"

namespace mocap::wire {
namespace {

bool SameHeader(const v1::MarkerFrame& a, const v1::MarkerFrame& b) {
  return a.node_id() == b.node_id() && a.frame_number() == b.frame_number() &&
         a.trigger_time_ns() == b.trigger_time_ns() && a.capture_time_ns() == b.capture_time_ns() &&
         a.exposure_us() == b.exposure_us() && a.width() == b.width() && a.height() == b.height() &&
         a.chunk_count() == b.chunk_count() && a.marker_total() == b.marker_total() &&
         a.flags() == b.flags();
}

}  // namespace

std::vector<v1::Packet> SplitMarkerFrame(const v1::MarkerFrame& frame) {
  const uint32_t total = static_cast<uint32_t>(frame.markers_size());
  const uint32_t count = total == 0 ? 1 : (total + kMarkersPerChunk - 1) / kMarkersPerChunk;
  std::vector<v1::Packet> packets(count);
  for (uint32_t i = 0; i < count; ++i) {
    v1::Packet& packet = packets[i];
    packet.set_version(kProtocolVersion);
    v1::MarkerFrame* chunk = packet.mutable_marker_frame();
    *chunk = frame;
    chunk->clear_markers();
    chunk->set_chunk_index(i);
    chunk->set_chunk_count(count);
    chunk->set_marker_total(total);
    chunk->set_first_marker(i * kMarkersPerChunk);
    const uint32_t end = std::min(total, (i + 1) * kMarkersPerChunk);
    for (uint32_t m = i * kMarkersPerChunk; m < end; ++m) *chunk->add_markers() = frame.markers(m);
  }
  return packets;
}

void ChunkAssembler::RememberCompleted(const Key& key) {
  completed_.insert(key);
  completed_order_.push_back(key);
  if (completed_order_.size() > max_pending_) {
    completed_.erase(completed_order_.front());
    completed_order_.pop_front();
  }
}

ChunkAssembler::Outcome ChunkAssembler::Add(const v1::MarkerFrame& chunk, v1::MarkerFrame* frame) {
  const Key key{chunk.frame_number(), chunk.node_id()};
  if (completed_.count(key)) return Outcome::kDuplicate;
  if (chunk.chunk_count() == 1) {
    *frame = chunk;
    RememberCompleted(key);
    return Outcome::kComplete;
  }
  Outcome outcome = Outcome::kIncomplete;
  auto it = pending_.find(key);
  if (it == pending_.end()) {
    if (pending_.size() >= max_pending_) {
      pending_.erase(pending_.begin());
      outcome = Outcome::kOverflow;
    }
    Partial partial;
    partial.header = chunk;
    partial.header.clear_markers();
    partial.chunks.resize(chunk.chunk_count());
    partial.received.assign(chunk.chunk_count(), false);
    it = pending_.emplace(key, std::move(partial)).first;
  }
  Partial& partial = it->second;
  if (!SameHeader(partial.header, chunk)) return Outcome::kInconsistent;
  if (partial.received[chunk.chunk_index()]) return Outcome::kDuplicate;
  partial.received[chunk.chunk_index()] = true;
  partial.chunks[chunk.chunk_index()] = chunk;
  if (++partial.received_count < partial.header.chunk_count()) return outcome;

  *frame = partial.header;
  frame->set_chunk_index(0);
  frame->set_chunk_count(1);
  frame->set_first_marker(0);
  for (const v1::MarkerFrame& part : partial.chunks)
    for (const v1::Marker& m : part.markers()) *frame->add_markers() = m;
  pending_.erase(it);
  RememberCompleted(key);
  return Outcome::kComplete;
}

size_t ChunkAssembler::DiscardBefore(uint64_t frame_number) {
  size_t discarded = 0;
  for (auto it = pending_.begin(); it != pending_.end() && it->first.first < frame_number;) {
    it = pending_.erase(it);
    ++discarded;
  }
  return discarded;
}

}  // namespace mocap::wire

// Splitting one camera frame's markers into datagram-sized chunks, and reassembling them exactly.
// Chunk i of a frame with N markers holds markers [48 i, min(48 (i+1), N)); an empty frame is one
// chunk. The assembler keeps a bounded number of partial frames and never trusts a chunk that
// disagrees with the ones already received for the same frame.
#pragma once

#include <cstdint>
#include <deque>
#include <map>
#include <set>
#include <utility>
#include <vector>

#include "mocap.pb.h"

namespace mocap::wire {

// `frame` holds all markers (chunk fields are ignored and filled in per chunk).
std::vector<v1::Packet> SplitMarkerFrame(const v1::MarkerFrame& frame);

class ChunkAssembler {
 public:
  enum class Outcome {
    kIncomplete,    // stored; more chunks to come
    kComplete,      // *frame holds every marker, chunk fields reset to a single chunk
    kDuplicate,     // this chunk (or its whole frame) was already received: dropped
    kInconsistent,  // header disagrees with earlier chunks of the same frame: dropped
    kOverflow,      // too many partial frames pending: the oldest was discarded to make room
  };

  explicit ChunkAssembler(size_t max_pending_frames = 1024) : max_pending_(max_pending_frames) {}

  Outcome Add(const v1::MarkerFrame& chunk, v1::MarkerFrame* frame);

  // Discards partial frames with a frame number below `frame_number`; returns how many.
  size_t DiscardBefore(uint64_t frame_number);
  size_t pending() const { return pending_.size(); }

 private:
  struct Partial {
    v1::MarkerFrame header;
    std::vector<v1::MarkerFrame> chunks;  // by chunk index; empty marker_total slot = missing
    std::vector<bool> received;
    uint32_t received_count = 0;
  };
  using Key = std::pair<uint64_t, uint32_t>;  // (frame number, node id)

  void RememberCompleted(const Key& key);

  size_t max_pending_;
  std::map<Key, Partial> pending_;
  // Recently completed frames, so that a chunk re-sent after completion counts as a duplicate
  // instead of opening a partial frame that can never complete.
  std::set<Key> completed_;
  std::deque<Key> completed_order_;
};

}  // namespace mocap::wire

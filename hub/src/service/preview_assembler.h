// Preview images from the nodes: PreviewChunk datagrams per node -> the whole 8-bit image once
// every chunk of one frame arrived -> PNG bytes for the operator. Chunks may arrive out of order
// or twice; a chunk of a newer frame replaces an older image still incomplete, one of an older
// frame is dropped; chunks that disagree about their frame's size, mode or chunk count, or that
// do not tile the image exactly, drop that image. Sizes are checked against limits before any
// memory is taken, and at most max_nodes images are assembled at once (the stalest goes).
// Pure: time is a parameter. Error policy: outside input never throws (outcomes say what
// happened); bad options throw std::invalid_argument from the constructor.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "mocap.pb.h"

namespace mocap::service {

struct PreviewAssemblerOptions {
  uint64_t max_image_bytes = 4096ull * 4096ull;  // width x height of one 8-bit preview
  uint32_t max_chunks = 16384;                   // chunks of one preview
  size_t max_nodes = 16;                         // previews assembled at once
  uint64_t stale_after_ns = 5'000'000'000;       // an incomplete preview idle this long is dropped

  // Empty when usable, otherwise why not.
  std::string Check() const;
};

struct PreviewImage {
  uint32_t node_id = 0;
  uint64_t frame_number = 0;
  bool thresholded = false;
  uint32_t width = 0;
  uint32_t height = 0;
  std::vector<uint8_t> pixels;  // row-major, width x height
};

// Lossless PNG of the image (8-bit grey). Throws std::runtime_error if encoding fails.
std::vector<uint8_t> EncodePng(const PreviewImage& image);

class PreviewAssembler {
 public:
  enum class Outcome {
    kIncomplete,    // stored, more chunks to come
    kComplete,      // *image holds the whole preview
    kDuplicate,     // this chunk was stored already
    kStale,         // an older frame than the one being assembled
    kInconsistent,  // disagrees with its frame's other chunks, or the chunks do not tile it
    kTooLarge,      // beyond max_image_bytes or max_chunks
  };

  explicit PreviewAssembler(PreviewAssemblerOptions options = {});

  // A chunk that passed wire::Decode, received at now_ns.
  Outcome Add(const v1::PreviewChunk& chunk, uint64_t now_ns, PreviewImage* image);
  // Drops incomplete previews idle since now_ns - stale_after_ns; returns how many.
  size_t DiscardStale(uint64_t now_ns);

  size_t assembling() const { return open_.size(); }

 private:
  struct Open {
    PreviewImage image;
    uint32_t chunk_count = 0;
    uint32_t chunks_seen = 0;
    uint64_t bytes_seen = 0;
    std::vector<uint8_t> seen;                          // per chunk index
    std::vector<std::pair<uint32_t, uint32_t>> spans;   // (offset, size) of the chunks stored
    uint64_t last_chunk_ns = 0;
  };
  PreviewAssemblerOptions options_;
  std::map<uint32_t, Open> open_;  // by node id
};

const char* PreviewOutcomeName(PreviewAssembler::Outcome outcome);

}  // namespace mocap::service

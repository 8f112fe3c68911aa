// Preview chunk assembly and PNG encoding (see preview_assembler.h).
#include "service/preview_assembler.h"

#include <algorithm>
#include <cstring>
#include <stdexcept>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

namespace mocap::service {

std::string PreviewAssemblerOptions::Check() const {
  if (max_image_bytes == 0) return "max_image_bytes must be > 0";
  if (max_chunks == 0) return "max_chunks must be > 0";
  if (max_nodes == 0) return "max_nodes must be > 0";
  if (stale_after_ns == 0) return "stale_after_ns must be > 0";
  return {};
}

const char* PreviewOutcomeName(PreviewAssembler::Outcome outcome) {
  switch (outcome) {
    case PreviewAssembler::Outcome::kIncomplete: return "incomplete";
    case PreviewAssembler::Outcome::kComplete: return "complete";
    case PreviewAssembler::Outcome::kDuplicate: return "duplicate";
    case PreviewAssembler::Outcome::kStale: return "stale";
    case PreviewAssembler::Outcome::kInconsistent: return "inconsistent";
    case PreviewAssembler::Outcome::kTooLarge: return "too-large";
  }
  return "unknown";
}

std::vector<uint8_t> EncodePng(const PreviewImage& image) {
  if (image.width == 0 || image.height == 0 || image.pixels.size() != uint64_t{image.width} * image.height)
    throw std::runtime_error("preview: image size does not match its pixels");
  // cv::Mat only wraps the pixels; imencode does not write through it.
  const cv::Mat grey(static_cast<int>(image.height), static_cast<int>(image.width), CV_8UC1,
                     const_cast<uint8_t*>(image.pixels.data()));
  std::vector<uint8_t> png;
  if (!cv::imencode(".png", grey, png)) throw std::runtime_error("preview: PNG encoding failed");
  return png;
}

PreviewAssembler::PreviewAssembler(PreviewAssemblerOptions options) : options_(options) {
  const std::string problem = options_.Check();
  if (!problem.empty()) throw std::invalid_argument("preview assembler: " + problem);
}

PreviewAssembler::Outcome PreviewAssembler::Add(const v1::PreviewChunk& chunk, uint64_t now_ns,
                                                PreviewImage* image) {
  const uint64_t bytes = uint64_t{chunk.width()} * chunk.height();
  if (bytes > options_.max_image_bytes || chunk.chunk_count() > options_.max_chunks) return Outcome::kTooLarge;
  const bool thresholded = chunk.mode() == v1::PREVIEW_MODE_THRESHOLDED;
  auto it = open_.find(chunk.node_id());
  if (it != open_.end()) {
    Open& o = it->second;
    if (chunk.frame_number() < o.image.frame_number) return Outcome::kStale;
    if (chunk.frame_number() == o.image.frame_number &&
        (chunk.width() != o.image.width || chunk.height() != o.image.height ||
         thresholded != o.image.thresholded || chunk.chunk_count() != o.chunk_count)) {
      open_.erase(it);
      return Outcome::kInconsistent;
    }
    if (chunk.frame_number() > o.image.frame_number) {
      open_.erase(it);
      it = open_.end();
    }
  }
  if (it == open_.end()) {
    if (open_.size() >= options_.max_nodes) {
      auto stalest = std::min_element(open_.begin(), open_.end(), [](const auto& a, const auto& b) {
        return a.second.last_chunk_ns < b.second.last_chunk_ns;
      });
      open_.erase(stalest);
    }
    Open o;
    o.image.node_id = chunk.node_id();
    o.image.frame_number = chunk.frame_number();
    o.image.thresholded = thresholded;
    o.image.width = chunk.width();
    o.image.height = chunk.height();
    o.image.pixels.assign(bytes, 0);
    o.chunk_count = chunk.chunk_count();
    o.seen.assign(chunk.chunk_count(), 0);
    it = open_.emplace(chunk.node_id(), std::move(o)).first;
  }
  Open& o = it->second;
  o.last_chunk_ns = now_ns;
  if (o.seen[chunk.chunk_index()]) return Outcome::kDuplicate;
  // The wire checked that the chunk lies inside the image.
  o.seen[chunk.chunk_index()] = 1;
  ++o.chunks_seen;
  o.bytes_seen += chunk.data().size();
  o.spans.emplace_back(chunk.offset(), static_cast<uint32_t>(chunk.data().size()));
  std::memcpy(o.image.pixels.data() + chunk.offset(), chunk.data().data(), chunk.data().size());
  if (o.bytes_seen > bytes) {
    open_.erase(it);
    return Outcome::kInconsistent;
  }
  if (o.chunks_seen < o.chunk_count) return Outcome::kIncomplete;
  // Every chunk is here: they must cover the image end to end without gap or overlap.
  std::sort(o.spans.begin(), o.spans.end());
  uint64_t end = 0;
  for (const auto& [offset, size] : o.spans) {
    if (offset != end) break;
    end += size;
  }
  if (end != bytes) {
    open_.erase(it);
    return Outcome::kInconsistent;
  }
  *image = std::move(o.image);
  open_.erase(it);
  return Outcome::kComplete;
}

size_t PreviewAssembler::DiscardStale(uint64_t now_ns) {
  size_t dropped = 0;
  for (auto it = open_.begin(); it != open_.end();) {
    if (now_ns >= it->second.last_chunk_ns + options_.stale_after_ns) {
      it = open_.erase(it);
      ++dropped;
    } else {
      ++it;
    }
  }
  return dropped;
}

}  // namespace mocap::service

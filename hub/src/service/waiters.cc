// Requests waiting on the loop for what the nodes send (see waiters.h).
#include "service/waiters.h"

#include <string>

#include "service/api_error.h"

namespace mocap::service {

std::future<RequestResult> Waiters::ForRequest(uint64_t request_id) {
  return requests_[request_id].get_future();
}

bool Waiters::Answer(const RequestResult& result) {
  auto waiter = requests_.find(result.request_id);
  if (waiter == requests_.end()) return false;
  waiter->second.set_value(result);
  requests_.erase(waiter);
  return true;
}

std::future<PreviewImage> Waiters::ForPreview(uint32_t node_id, bool thresholded, uint64_t deadline_ns) {
  PreviewWait& wait = previews_.emplace_back();
  wait.node_id = node_id;
  wait.thresholded = thresholded;
  wait.deadline_ns = deadline_ns;
  return wait.promise.get_future();
}

void Waiters::Answer(const PreviewImage& image) {
  for (auto it = previews_.begin(); it != previews_.end();) {
    if (it->node_id == image.node_id && it->thresholded == image.thresholded) {
      it->promise.set_value(image);
      it = previews_.erase(it);
    } else {
      ++it;
    }
  }
}

std::future<BlobsSnapshot> Waiters::ForBlobs(uint64_t now_ns, const std::vector<CameraMask>& masks) {
  BlobsWait wait;
  wait.deadline_ns = now_ns + blobs_wait_ns_;
  std::future<BlobsSnapshot> future = wait.promise.get_future();
  if (now_ns > last_set_ns_ + blobs_wait_ns_)
    wait.promise.set_value(BlobsSnapshot{std::nullopt, masks});  // nothing flows: don't wait
  else
    blobs_.push_back(std::move(wait));
  return future;
}

std::future<std::vector<FrameSet>> Waiters::ForFrameSets(size_t count, uint64_t deadline_ns) {
  FrameSetsWait wait;
  wait.count = count;
  wait.deadline_ns = deadline_ns;
  wait.sets.reserve(count);
  std::future<std::vector<FrameSet>> future = wait.promise.get_future();
  frame_sets_.push_back(std::move(wait));
  return future;
}

void Waiters::OnFrameSet(const FrameSet& set, const std::vector<CameraMask>& masks, uint64_t now_ns) {
  last_set_ns_ = now_ns;
  for (BlobsWait& wait : blobs_) wait.promise.set_value(BlobsSnapshot{set, masks});
  blobs_.clear();
  for (auto it = frame_sets_.begin(); it != frame_sets_.end();) {
    it->sets.push_back(set);
    if (it->sets.size() < it->count) {
      ++it;
      continue;
    }
    it->promise.set_value(std::move(it->sets));
    it = frame_sets_.erase(it);
  }
}

void Waiters::Expire(uint64_t now_ns, const std::vector<CameraMask>& masks) {
  for (auto it = previews_.begin(); it != previews_.end();) {
    if (now_ns < it->deadline_ns) {
      ++it;
      continue;
    }
    it->promise.set_exception(std::make_exception_ptr(
        ApiError(504, "node " + std::to_string(it->node_id) + " sent no complete preview in time")));
    it = previews_.erase(it);
  }
  for (auto it = blobs_.begin(); it != blobs_.end();) {
    if (now_ns < it->deadline_ns) {
      ++it;
      continue;
    }
    it->promise.set_value(BlobsSnapshot{std::nullopt, masks});
    it = blobs_.erase(it);
  }
  for (auto it = frame_sets_.begin(); it != frame_sets_.end();) {
    if (now_ns < it->deadline_ns) {
      ++it;
      continue;
    }
    it->promise.set_value(std::move(it->sets));
    it = frame_sets_.erase(it);
  }
}

}  // namespace mocap::service

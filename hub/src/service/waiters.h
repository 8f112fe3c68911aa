// Requests from other threads that wait on the loop for something the nodes send: a control
// request's outcome, a node's preview image, the next frame set's blobs, a window of frame sets. One object on the loop
// (pure: time passed in): a waiter is a promise kept until its answer comes or its deadline
// passes (a preview then fails with ApiError 504, a blobs waiter gets no frame set).
//
// Threads: loop only; the futures it hands out are waited on by the requesting threads.
#pragma once

#include <cstdint>
#include <future>
#include <map>
#include <optional>
#include <vector>

#include "ingest/camera_frame.h"
#include "service/auto_mask.h"
#include "service/control_requests.h"
#include "service/preview_assembler.h"

namespace mocap::service {

// The answer to a blobs waiter: the frame set (none: no frame set in time) and the masks then.
struct BlobsSnapshot {
  std::optional<FrameSet> set;
  std::vector<CameraMask> masks;
};

class Waiters {
 public:
  // blobs_wait_ns: how long a blobs waiter waits for the next frame set, and how long without
  // one after which frame sets count as not flowing (then a blobs waiter is answered at once).
  explicit Waiters(uint64_t blobs_wait_ns) : blobs_wait_ns_(blobs_wait_ns) {}

  // The outcome of the request request_id, when Answer gets it (the request's own timeout ends it).
  std::future<RequestResult> ForRequest(uint64_t request_id);
  // False when nobody waits for this request.
  bool Answer(const RequestResult& result);

  // The next complete preview of node_id in the mode asked, until deadline_ns.
  std::future<PreviewImage> ForPreview(uint32_t node_id, bool thresholded, uint64_t deadline_ns);
  void Answer(const PreviewImage& image);

  // The next frame set's blobs and `masks` then; answered at once with no frame set (and
  // `masks`) when none came for blobs_wait_ns.
  std::future<BlobsSnapshot> ForBlobs(uint64_t now_ns, const std::vector<CameraMask>& masks);
  // The next `count` frame sets (the floor / L-frame step's window), answered when they are in
  // or, with those that came, at deadline_ns.
  std::future<std::vector<FrameSet>> ForFrameSets(size_t count, uint64_t deadline_ns);
  // A frame set published at now_ns: every blobs and frame-set waiter gets it (copied only when one waits).
  void OnFrameSet(const FrameSet& set, const std::vector<CameraMask>& masks, uint64_t now_ns);

  // Answers the waiters whose deadline passed at now_ns.
  void Expire(uint64_t now_ns, const std::vector<CameraMask>& masks);

 private:
  struct PreviewWait {
    uint32_t node_id = 0;
    bool thresholded = false;
    uint64_t deadline_ns = 0;
    std::promise<PreviewImage> promise;
  };
  struct BlobsWait {
    uint64_t deadline_ns = 0;
    std::promise<BlobsSnapshot> promise;
  };
  struct FrameSetsWait {
    size_t count = 0;
    uint64_t deadline_ns = 0;
    std::vector<FrameSet> sets;
    std::promise<std::vector<FrameSet>> promise;
  };

  uint64_t blobs_wait_ns_;
  uint64_t last_set_ns_ = 0;
  std::map<uint64_t, std::promise<RequestResult>> requests_;
  std::vector<PreviewWait> previews_;
  std::vector<BlobsWait> blobs_;
  std::vector<FrameSetsWait> frame_sets_;
};

}  // namespace mocap::service

// One automatic-mask request in `serve` (POST /api/masks/auto), as one object on the loop: the
// frame sets collected, the masks computed from them (auto_mask.h) on top of the masks the
// nodes already apply, the nodes' requests in flight, and the answer the caller waits for.
// HubService sends the requests and keeps the installation's masks; this object decides when
// the job is done and what it answers. Pure: time is passed in, no sockets.
//
// Error policy: a failed job answers its caller with ApiError (504: too few frames in time, no
// camera with enough frames; 500: a request the control layer refused).
#pragma once

#include <cstdint>
#include <functional>
#include <future>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "ingest/camera_frame.h"
#include "service/auto_mask.h"

namespace mocap::service {

class AutoMaskJob {
 public:
  AutoMaskJob(int frames_wanted, uint64_t deadline_ns) : frames_wanted_(frames_wanted), deadline_ns_(deadline_ns) {}

  std::future<nlohmann::json> Answer() { return promise_.get_future(); }

  bool collecting() const { return frames_seen_ < frames_wanted_; }
  // A frame set while collecting; true when it was the last one wanted.
  bool Collect(const FrameSet& set);
  // The masks of the collected frames, each camera's kept masks (`kept`) added, for the cameras
  // `known` says the registry knows; the collected frames are dropped. Empty: no camera had
  // enough frames (the job has then failed).
  const std::vector<CameraMask>& ComputeMasks(const std::vector<CameraMask>& kept,
                                              const std::function<bool(uint32_t camera_id)>& known);
  // A node's request for `camera_id`'s mask is in flight.
  void Sent(uint64_t request_id, uint32_t camera_id) { requests_[request_id] = camera_id; }
  // A finished request: false when it is not one of this job's; `result` is its JSON.
  bool Finished(uint64_t request_id, nlohmann::json result);
  // Collected and every node's request finished: the masks are the installation's now.
  bool AllAnswered() const { return !collecting() && requests_.empty(); }
  // Collecting still, after the deadline.
  bool TimedOut(uint64_t now_ns) const { return collecting() && now_ns >= deadline_ns_; }

  const std::vector<CameraMask>& masks() const { return masks_; }
  // {"frames", "cameras": [{"camera_id", "static_blobs_found", "regions"}], "masks", "nodes", "file"}
  void Succeed(const nlohmann::json& masks, const std::string& file);
  void Fail(int status, const std::string& reason);
  // "only N of M frame sets arrived in time (are the nodes running?)"
  std::string TimeoutReason() const;

 private:
  int frames_wanted_;
  int frames_seen_ = 0;
  uint64_t deadline_ns_;
  std::map<uint32_t, std::vector<CameraFrame>> frames_;  // by camera id
  std::vector<CameraMask> masks_;
  std::map<uint64_t, uint32_t> requests_;                // request id -> camera id
  nlohmann::json results_ = nlohmann::json::array();
  nlohmann::json found_ = nlohmann::json::array();       // per camera: new static blobs, regions
  std::promise<nlohmann::json> promise_;
};

}  // namespace mocap::service

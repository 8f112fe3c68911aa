// One automatic-mask request (see auto_mask_job.h).
#include "service/auto_mask_job.h"

#include <algorithm>
#include <exception>
#include <utility>

#include "service/api_error.h"
#include "util/log.h"

namespace mocap::service {

bool AutoMaskJob::Collect(const FrameSet& set) {
  if (!collecting()) return false;
  for (const CameraFrame& camera : set.cameras) frames_[camera.camera_id].push_back(camera);
  return ++frames_seen_ == frames_wanted_;
}

const std::vector<CameraMask>& AutoMaskJob::ComputeMasks(const std::vector<CameraMask>& kept,
                                                         const std::function<bool(uint32_t camera_id)>& known) {
  AutoMaskOptions options;
  options.min_frames = std::min<size_t>(options.min_frames, static_cast<size_t>(frames_wanted_));
  for (auto& [camera, frames] : frames_) {
    if (!known(camera)) continue;
    try {
      CameraMask mask = ComputeAutoMask(frames, options);
      found_.push_back({{"camera_id", camera}, {"static_blobs_found", mask.blobs.size()}});
      // Masks add up, as the commercial consoles' "mask visible" does: what the nodes mask
      // already is invisible in these frames and must stay masked (`mask clear` removes all).
      for (const CameraMask& k : kept) {
        if (k.camera_id != camera) continue;
        mask.blobs.insert(mask.blobs.end(), k.blobs.begin(), k.blobs.end());
        mask.regions.insert(mask.regions.end(), k.regions.begin(), k.regions.end());
      }
      found_.back()["regions"] = mask.regions.size();
      masks_.push_back(std::move(mask));
    } catch (const std::exception& e) {
      log::Warn("camera {}: no mask: {}", camera, e.what());
    }
  }
  frames_.clear();
  if (masks_.empty()) Fail(504, "no camera delivered enough frames for a mask");
  return masks_;
}

bool AutoMaskJob::Finished(uint64_t request_id, nlohmann::json result) {
  const auto part = requests_.find(request_id);
  if (part == requests_.end()) return false;
  results_.push_back(std::move(result));
  requests_.erase(part);
  return true;
}

void AutoMaskJob::Succeed(const nlohmann::json& masks, const std::string& file) {
  promise_.set_value({{"frames", frames_seen_}, {"cameras", found_}, {"masks", masks}, {"nodes", results_},
                      {"file", file}});
}

void AutoMaskJob::Fail(int status, const std::string& reason) {
  promise_.set_exception(std::make_exception_ptr(ApiError(status, reason)));
}

std::string AutoMaskJob::TimeoutReason() const {
  return "only " + std::to_string(frames_seen_) + " of " + std::to_string(frames_wanted_) +
         " frame sets arrived in time (are the nodes running?)";
}

}  // namespace mocap::service

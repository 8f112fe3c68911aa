// Frames of another image size than the calibration's: rescaled or refused (image_size_check.h).
#include "ingest/image_size_check.h"

#include <algorithm>
#include <cmath>

#include "util/log.h"

namespace mocap {
namespace {

std::string SizeText(uint32_t width, uint32_t height) { return std::to_string(width) + "x" + std::to_string(height); }

}  // namespace

ImageSizes ImageSizesOf(const Rig& rig) {
  ImageSizes sizes;
  for (const Camera& camera : rig.cameras) {
    if (camera.intrinsics.width > 0 && camera.intrinsics.height > 0)
      sizes[camera.id] = {static_cast<uint32_t>(camera.intrinsics.width), static_cast<uint32_t>(camera.intrinsics.height)};
  }
  return sizes;
}

ImageSizeVerdict ImageSizeCheck::Apply(CameraFrame* frame) {
  const auto calibrated = calibrated_.find(frame->camera_id);
  if (calibrated == calibrated_.end() || frame->width == 0 || frame->height == 0) return ImageSizeVerdict::kSame;
  const ImageSize want = calibrated->second;
  if (frame->width == want.width && frame->height == want.height) return ImageSizeVerdict::kSame;

  ImageSizeCounts& counts = counts_[frame->camera_id];
  counts.last_other = {frame->width, frame->height};
  const bool same_aspect =
      static_cast<uint64_t>(frame->width) * want.height == static_cast<uint64_t>(frame->height) * want.width;
  const double scale = static_cast<double>(want.width) / frame->width;
  if (logged_.insert({frame->camera_id, frame->width, frame->height}).second) {
    const std::string sizes = "camera " + std::to_string(frame->camera_id) + " sends " +
                              SizeText(frame->width, frame->height) + " images, calibrated at " +
                              SizeText(want.width, want.height);
    if (same_aspect)
      log::Warn("{}: its centroids are rescaled by {:.4g} (a binned or scaled sensor mode); calibrate in this "
                "mode for full accuracy",
                sizes, scale);
    else
      log::Warn("{} (another aspect ratio: a cropped or different sensor mode): its frames are refused; set the "
                "node to {} or recalibrate it",
                sizes, SizeText(want.width, want.height));
  }
  if (!same_aspect) {
    ++counts.refused_frames;
    return ImageSizeVerdict::kRefused;
  }
  for (Blob& blob : frame->blobs) {
    blob.pixel = (blob.pixel.array() + 0.5) * scale - 0.5;
    blob.area = static_cast<uint32_t>(std::lround(std::min(blob.area * scale * scale, 4294967295.0)));
  }
  frame->width = want.width;
  frame->height = want.height;
  ++counts.rescaled_frames;
  return ImageSizeVerdict::kRescaled;
}

std::vector<std::string> ImageSizeCheck::Summary() const {
  std::vector<std::string> out;
  for (const auto& [camera, counts] : counts_) {
    const ImageSize want = calibrated_.at(camera);
    std::string line = "camera " + std::to_string(camera) + ": images of " +
                       SizeText(counts.last_other.width, counts.last_other.height) + " against a calibration at " +
                       SizeText(want.width, want.height) + ": ";
    if (counts.rescaled_frames) line += std::to_string(counts.rescaled_frames) + " frames rescaled";
    if (counts.rescaled_frames && counts.refused_frames) line += ", ";
    if (counts.refused_frames) line += std::to_string(counts.refused_frames) + " frames refused (another aspect ratio)";
    out.push_back(line);
  }
  return out;
}

}  // namespace mocap

// Camera frames whose image size differs from the calibration's. A node streaming a binned or
// scaled sensor mode (640x400 against a calibration made at 1280x800) sends centroids on another
// pixel scale; used as they are, its rays are off by up to half the image. What is done:
// - the same aspect ratio (width * H == height * W exactly): the centroids are rescaled to the
//   calibration's pixels, with pixel centres at integer coordinates (OpenCV):
//   x_cal = (x + 0.5) * W / width - 0.5, and blob areas by the square of the factor;
// - any other size (another aspect ratio: a cropped region of interest, another sensor mode):
//   the camera's frames are refused, since no scale maps them onto the calibration;
// - frames that report no size (0 x 0) and cameras calibrated without one are used unchanged.
// Both are counted per camera and logged once per camera and size, naming both sizes and what to
// do. A crop with the calibration's aspect ratio cannot be told from a binned mode on the wire
// (frames carry no offset) and is rescaled: calibrated installations must not use ROI modes.
// Pure bookkeeping plus one log line per new size; no exceptions.
#pragma once

#include <cstdint>
#include <map>
#include <set>
#include <string>
#include <tuple>
#include <vector>

#include "geometry/camera.h"
#include "ingest/camera_frame.h"

namespace mocap {

struct ImageSize {
  uint32_t width = 0;
  uint32_t height = 0;
};

// Camera id -> the image size its calibration was made at.
using ImageSizes = std::map<uint32_t, ImageSize>;
ImageSizes ImageSizesOf(const Rig& rig);

enum class ImageSizeVerdict {
  kSame,      // as calibrated (or nothing to compare)
  kRescaled,  // same aspect ratio: centroids rescaled to the calibration's pixels
  kRefused,   // another aspect ratio: do not use the frame
};

struct ImageSizeCounts {
  uint64_t rescaled_frames = 0;
  uint64_t refused_frames = 0;
  ImageSize last_other;  // the last size that differed from the calibration's
};

class ImageSizeCheck {
 public:
  ImageSizeCheck() = default;
  explicit ImageSizeCheck(ImageSizes calibrated) : calibrated_(std::move(calibrated)) {}
  // Rescales the frame's blobs in place when that is the verdict.
  ImageSizeVerdict Apply(CameraFrame* frame);
  // What Apply did to each camera whose frames differed (cameras that never did are absent).
  const std::map<uint32_t, ImageSizeCounts>& counts() const { return counts_; }
  // One line per camera that differed (empty when none did): for warnings and reports.
  std::vector<std::string> Summary() const;

 private:
  ImageSizes calibrated_;
  std::map<uint32_t, ImageSizeCounts> counts_;
  std::set<std::tuple<uint32_t, uint32_t, uint32_t>> logged_;  // camera, width, height
};

}  // namespace mocap

// Detection speed per camera pixel format (mocap-detect-bench --formats): the bench's frames
// packed as a camera delivers them (planar YUV with the Y plane first, packed YUV, packed RGB,
// 10/16-bit grey and, with libjpeg-turbo, MJPEG at quality 90, 4:2:2), then timed through what
// the node does with each (the Y plane in place, mn_pixfmt_to_y8, mn_mjpeg_to_y8) followed by
// detection. Grey pixels in every format (chroma 128, R = G = B), so each format's luma is the
// frame again and gives the same blobs (checked, except MJPEG, which is lossy).
#pragma once

#include <string>
#include <vector>

#include "detect-bench/frame_set.h"
#include "detect/detect.h"

namespace mocap {

struct FormatTiming {
  std::string name;        // V4L2 fourcc name
  double convert_ms = 0;   // per frame, to 8-bit luma (0 for the in-place formats)
  double total_ms = 0;     // per frame, conversion + detection
  bool lossless = true;    // the format carries the luma exactly (not MJPEG)
  bool same_blobs = true;  // a lossless format's luma gave exactly the original frame's blobs
};

std::vector<FormatTiming> TimeFormats(const std::vector<BenchFrame>& frames, mn_detector* det,
                                      int repeat);

}  // namespace mocap

// The OpenCV pipeline the detector is compared with (threshold, open + close with a 3x3
// square, connectedComponentsWithStats, intensity-weighted centroids), and the double-precision
// reference centroids of the detector's definition computed from the same components.
#pragma once

#include <cstdint>
#include <vector>

#include <opencv2/core.hpp>

#include "detect-bench/frame_set.h"

namespace mocap {

struct RefCentroid {
  double x = 0.0, y = 0.0;
  uint32_t area = 0;
};

class OpenCvPipeline {
 public:
  // Foreground is value > threshold; morph_radius 0 skips the open and close.
  OpenCvPipeline(int threshold, int morph_radius);

  // Runs the whole pipeline on one frame; centroids in pixel-centre coordinates, weights
  // value - threshold (0 for pixels the closing added below it), as our detector uses.
  void Run(const BenchFrame& frame, std::vector<RefCentroid>* out);

  // Reference for our detector, in double precision from OpenCV's components: the detector
  // uses morphology only to segment, so a component's centroid also counts the above-threshold
  // pixels of its pre-morphology region within the radius of it that no earlier component
  // (in label order) took. Not timed.
  void Reference(const BenchFrame& frame, std::vector<RefCentroid>* out);

 private:
  int threshold_;
  int morph_radius_;
  cv::Mat kernel_, binary_, scratch_, labels_, stats_, centroids_;
  cv::Mat ref_binary_, ref_regions_, ref_claimed_;
};

}  // namespace mocap

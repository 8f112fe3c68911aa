// OpenCV pipeline: whole-frame threshold and morphology, then labelling with statistics, then
// one pass over each component's bounding box for intensity-weighted centroids in double.
#include "bench/opencv_pipeline.h"

#include <opencv2/imgproc.hpp>

namespace mocap {

OpenCvPipeline::OpenCvPipeline(int threshold, int morph_radius)
    : threshold_(threshold), morph_radius_(morph_radius) {
  const int side = 2 * morph_radius + 1;
  kernel_ = cv::getStructuringElement(cv::MORPH_RECT, cv::Size(side, side));
}

void OpenCvPipeline::Run(const BenchFrame& frame, std::vector<RefCentroid>* out) {
  const cv::Mat src(static_cast<int>(frame.height), static_cast<int>(frame.width), CV_8U,
                    const_cast<uint8_t*>(frame.pixels.data()));
  cv::threshold(src, binary_, threshold_, 255, cv::THRESH_BINARY);
  if (morph_radius_ > 0) {
    cv::morphologyEx(binary_, scratch_, cv::MORPH_OPEN, kernel_);
    cv::morphologyEx(scratch_, binary_, cv::MORPH_CLOSE, kernel_);
  }
  const int n = cv::connectedComponentsWithStats(binary_, labels_, stats_, centroids_, 8, CV_32S);
  out->assign(n > 0 ? static_cast<size_t>(n - 1) : 0, RefCentroid());
  for (int l = 1; l < n; ++l) {
    const int x0 = stats_.at<int>(l, cv::CC_STAT_LEFT), y0 = stats_.at<int>(l, cv::CC_STAT_TOP);
    const int bw = stats_.at<int>(l, cv::CC_STAT_WIDTH), bh = stats_.at<int>(l, cv::CC_STAT_HEIGHT);
    double sw = 0.0, sx = 0.0, sy = 0.0, bx = 0.0, by = 0.0;
    uint32_t area = 0;
    for (int y = y0; y < y0 + bh; ++y) {
      const int* lab = labels_.ptr<int>(y);
      const uint8_t* px = src.ptr<uint8_t>(y);
      for (int x = x0; x < x0 + bw; ++x) {
        if (lab[x] != l) continue;
        const double w = px[x] > threshold_ ? px[x] - threshold_ : 0.0;
        sw += w;
        sx += w * x;
        sy += w * y;
        bx += x;
        by += y;
        ++area;
      }
    }
    RefCentroid& c = (*out)[static_cast<size_t>(l - 1)];
    c.area = area;
    // A component made only of pixels the closing added has no weight: use its plain mean.
    c.x = sw > 0.0 ? sx / sw : bx / area;
    c.y = sw > 0.0 ? sy / sw : by / area;
  }
}

}  // namespace mocap

// OpenCV pipeline: whole-frame threshold and morphology, then labelling with statistics, then
// one pass over each component's bounding box for intensity-weighted centroids in double.
#include "detect-bench/opencv_pipeline.h"

#include <algorithm>

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

void OpenCvPipeline::Reference(const BenchFrame& frame, std::vector<RefCentroid>* out) {
  const cv::Mat src(static_cast<int>(frame.height), static_cast<int>(frame.width), CV_8U,
                    const_cast<uint8_t*>(frame.pixels.data()));
  cv::threshold(src, ref_binary_, threshold_, 255, cv::THRESH_BINARY);
  cv::connectedComponents(ref_binary_, ref_regions_, 8, CV_32S);
  Run(frame, out);  // leaves the components in labels_ and stats_
  ref_claimed_ = cv::Mat::zeros(src.size(), CV_8U);
  const int r = morph_radius_, w = src.cols, h = src.rows;
  for (size_t i = 0; i < out->size(); ++i) {
    const int l = static_cast<int>(i) + 1;
    const int bx = stats_.at<int>(l, cv::CC_STAT_LEFT), by = stats_.at<int>(l, cv::CC_STAT_TOP);
    const int bw = stats_.at<int>(l, cv::CC_STAT_WIDTH), bh = stats_.at<int>(l, cv::CC_STAT_HEIGHT);
    int region = 0;
    for (int y = by; y < by + bh && !region; ++y)
      for (int x = bx; x < bx + bw && !region; ++x)
        if (labels_.at<int>(y, x) == l && ref_binary_.at<uint8_t>(y, x))
          region = ref_regions_.at<int>(y, x);
    double sw = 0.0, sx = 0.0, sy = 0.0, mx = 0.0, my = 0.0;
    uint32_t area = 0;
    for (int y = std::max(0, by - r); y < std::min(h, by + bh + r); ++y) {
      for (int x = std::max(0, bx - r); x < std::min(w, bx + bw + r); ++x) {
        bool in = labels_.at<int>(y, x) == l;
        if (!in && ref_binary_.at<uint8_t>(y, x) && ref_regions_.at<int>(y, x) == region &&
            !ref_claimed_.at<uint8_t>(y, x)) {
          for (int dy = -r; dy <= r && !in; ++dy)
            for (int dx = -r; dx <= r && !in; ++dx) {
              const int nx = x + dx, ny = y + dy;
              in = nx >= 0 && ny >= 0 && nx < w && ny < h && labels_.at<int>(ny, nx) == l;
            }
        }
        if (!in) continue;
        ref_claimed_.at<uint8_t>(y, x) = 1;
        const int v = src.at<uint8_t>(y, x);
        const double wgt = v > threshold_ ? v - threshold_ : 0.0;
        sw += wgt;
        sx += wgt * x;
        sy += wgt * y;
        mx += x;
        my += y;
        ++area;
      }
    }
    RefCentroid& c = (*out)[i];
    c.area = area;
    c.x = sw > 0.0 ? sx / sw : mx / area;
    c.y = sw > 0.0 ? sy / sw : my / area;
  }
}

}  // namespace mocap

// mocap-detect-bench: times, on the same in-memory frames, (a) our detector, (b) the plain read
// pass over every pixel (the memory-bound floor) and (c) an OpenCV pipeline doing the same job,
// and checks our centroids against a double-precision reference. Also writes synthetic frames.
#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "detect-bench/bench_formats.h"
#include "detect-bench/bench_timing.h"
#include "detect-bench/frame_set.h"
#include "detect-bench/make_frames.h"
#include "detect-bench/opencv_pipeline.h"
#include "detect-bench/read_pass.h"
#include "detect/detect.h"

namespace mocap {
namespace {

const char kUsage[] =
    "usage: mocap-detect-bench --frames DIR [--json] [--threshold T] [--morph-radius R]\n"
    "                          [--max-frames N] [--repeat K] [--formats]\n"
    "       mocap-detect-bench --make-frames DIR [--count N] [--markers M] [--width W]\n"
    "                          [--height H] [--seed S]\n";

struct Args {
  std::string frames_dir, make_dir;
  bool json = false;
  bool formats = false;  // also time each camera pixel format's conversion + detection
  int threshold = 40;
  int morph_radius = 1;
  size_t max_frames = 60;
  int repeat = 5;
  MakeFramesOptions make;
};

uint64_t ParseUint(const std::string& flag, const char* text, uint64_t lo, uint64_t hi) {
  char* end = nullptr;
  errno = 0;
  const unsigned long long v = std::strtoull(text, &end, 10);
  if (errno != 0 || end == text || *end != '\0' || text[0] == '-' || v < lo || v > hi)
    throw std::invalid_argument(flag + " needs an integer in " + std::to_string(lo) + ".." +
                                std::to_string(hi) + ", got '" + text + "'");
  return v;
}

Args ParseArgs(int argc, char** argv) {
  Args a;
  for (int i = 1; i < argc; ++i) {
    const std::string flag = argv[i];
    if (flag == "--json") {
      a.json = true;
      continue;
    }
    if (flag == "--formats") {
      a.formats = true;
      continue;
    }
    if (flag == "--help" || flag == "-h") {
      std::fputs(kUsage, stdout);
      std::exit(0);
    }
    if (i + 1 >= argc) throw std::invalid_argument("missing value after " + flag);
    const char* v = argv[++i];
    if (flag == "--frames") a.frames_dir = v;
    else if (flag == "--make-frames") a.make_dir = v;
    else if (flag == "--threshold") a.threshold = static_cast<int>(ParseUint(flag, v, 0, 254));
    else if (flag == "--morph-radius") a.morph_radius = static_cast<int>(ParseUint(flag, v, 0, 8));
    else if (flag == "--max-frames") a.max_frames = ParseUint(flag, v, 1, 100000);
    else if (flag == "--repeat") a.repeat = static_cast<int>(ParseUint(flag, v, 1, 1000));
    else if (flag == "--count") a.make.count = static_cast<uint32_t>(ParseUint(flag, v, 1, 100000));
    else if (flag == "--markers") a.make.markers = static_cast<uint32_t>(ParseUint(flag, v, 0, 100000));
    else if (flag == "--width") a.make.width = static_cast<uint32_t>(ParseUint(flag, v, 16, 16384));
    else if (flag == "--height") a.make.height = static_cast<uint32_t>(ParseUint(flag, v, 16, 16384));
    else if (flag == "--seed") a.make.seed = ParseUint(flag, v, 0, UINT64_MAX);
    else throw std::invalid_argument("unknown option " + flag);
  }
  if (a.frames_dir.empty() == a.make_dir.empty())
    throw std::invalid_argument("give exactly one of --frames DIR and --make-frames DIR");
  return a;
}

struct Accuracy {
  double max_diff = 0.0;
  size_t ours = 0, reference = 0, matched = 0;
};

// Pairs each of our blobs with the nearest reference blob of the same area within 1 px: the same
// pixels, so the difference measures the centroid arithmetic. Blobs the two segment differently
// (the whole-frame closing joins markers 1-2 px apart that ours keeps apart) stay unpaired,
// rather than pairing one of two markers with their joint centroid.
void Compare(const std::vector<mn_blob>& ours, const std::vector<RefCentroid>& ref,
             Accuracy* acc) {
  acc->ours += ours.size();
  acc->reference += ref.size();
  for (const mn_blob& b : ours) {
    double best = 1.0;
    bool found = false;
    for (const RefCentroid& r : ref) {
      if (r.area != b.area) continue;
      const double d = std::hypot(b.x - r.x, b.y - r.y);
      if (d < best) {
        best = d;
        found = true;
      }
    }
    if (!found) continue;
    ++acc->matched;
    acc->max_diff = std::max(acc->max_diff, best);
  }
}

int RunBench(const Args& a) {
  const std::vector<BenchFrame> frames = LoadFrames(a.frames_dir, a.max_frames);
  uint32_t max_w = 0, max_h = 0;
  for (const BenchFrame& f : frames) {
    max_w = std::max(max_w, f.width);
    max_h = std::max(max_h, f.height);
  }

  mn_detect_config cfg;
  mn_detect_config_default(&cfg);
  cfg.threshold = static_cast<uint8_t>(a.threshold);
  cfg.morph_radius = static_cast<uint8_t>(a.morph_radius);
  // No filtering, so that every component can be paired with OpenCV's.
  cfg.min_area = 1;
  cfg.max_area = max_w * max_h;
  cfg.max_bbox = 1024;
  cfg.max_blobs = 65536;
  mn_detector* det = mn_detector_new(&cfg, max_w, max_h);
  if (!det) throw std::runtime_error("cannot create the detector");
  std::vector<mn_blob> blobs(cfg.max_blobs);
  size_t n_blobs = 0;

  // OpenCV on one thread, like the node's single-threaded loop.
  cv::setNumThreads(1);
  OpenCvPipeline cv_pipe(a.threshold, a.morph_radius);
  std::vector<RefCentroid> ref;

  Accuracy acc;
  for (const BenchFrame& f : frames) {
    if (mn_detector_run(det, f.pixels.data(), f.width, f.height, f.width, blobs.data(),
                        blobs.size(), &n_blobs) != 0)
      throw std::runtime_error("detector refused a frame");
    cv_pipe.Reference(f, &ref);
    Compare(std::vector<mn_blob>(blobs.begin(), blobs.begin() + n_blobs), ref, &acc);
  }

  volatile uint64_t sink = 0;
  const double ours_ms = TimePerFrame(frames, a.repeat, [&](const BenchFrame& f) {
    mn_detector_run(det, f.pixels.data(), f.width, f.height, f.width, blobs.data(), blobs.size(),
                    &n_blobs);
    sink = sink + n_blobs;
  });
  const double read_ms = TimePerFrame(frames, a.repeat, [&](const BenchFrame& f) {
    sink = sink + mn_bench_read_pass(f.pixels.data(), f.width, f.height, f.width);
  });
  const double cv_ms = TimePerFrame(frames, a.repeat, [&](const BenchFrame& f) {
    cv_pipe.Run(f, &ref);
    sink = sink + ref.size();
  });
  std::vector<FormatTiming> formats;
  if (a.formats) formats = TimeFormats(frames, det, a.repeat);
  mn_detector_free(det);
  bool formats_ok = true;
  for (const FormatTiming& t : formats) formats_ok = formats_ok && t.same_blobs;

  const double per_frame = static_cast<double>(acc.ours) / frames.size();
  if (a.json) {
    std::printf(
        "{\"frames\": %zu, \"width\": %u, \"height\": %u, \"blobs_per_frame\": %.2f, "
        "\"ours_ms_per_frame\": %.5f, \"read_pass_ms_per_frame\": %.5f, "
        "\"opencv_ms_per_frame\": %.5f, \"ours_over_read_pass\": %.3f, "
        "\"opencv_over_ours\": %.2f, \"max_centroid_diff_px\": %.3g, "
        "\"blobs_ours\": %zu, \"blobs_reference\": %zu, \"blobs_matched\": %zu}\n",
        frames.size(), max_w, max_h, per_frame, ours_ms, read_ms, cv_ms, ours_ms / read_ms,
        cv_ms / ours_ms, acc.max_diff, acc.ours, acc.reference, acc.matched);
    for (const FormatTiming& t : formats)
      std::printf("{\"format\": \"%s\", \"convert_ms_per_frame\": %.5f, "
                  "\"total_ms_per_frame\": %.5f, \"same_blobs\": %s}\n",
                  t.name.c_str(), t.convert_ms, t.total_ms,
                  t.lossless ? (t.same_blobs ? "true" : "false") : "null");
  } else {
    std::printf("frames: %zu (up to %ux%u), %.1f blobs per frame, threshold %d, morph radius %d\n",
                frames.size(), max_w, max_h, per_frame, a.threshold, a.morph_radius);
    std::printf("ours:      %8.4f ms/frame\n", ours_ms);
    std::printf("read pass: %8.4f ms/frame  (ours / read pass = %.2fx)\n", read_ms,
                ours_ms / read_ms);
    std::printf("opencv:    %8.4f ms/frame  (opencv / ours = %.1fx)\n", cv_ms, cv_ms / ours_ms);
    std::printf("centroids: max difference from the double-precision reference %.3g px "
                "(%zu of our %zu blobs paired, reference has %zu)\n",
                acc.max_diff, acc.matched, acc.ours, acc.reference);
    if (!formats.empty())
      std::printf("format  to luma ms/frame  + detection ms/frame  blobs\n");
    for (const FormatTiming& t : formats)
      std::printf("%-6s  %16.4f  %20.4f  %s\n", t.name.c_str(), t.convert_ms, t.total_ms,
                  !t.lossless ? "(lossy)" : t.same_blobs ? "same" : "DIFFERENT");
  }
  // A lossless format whose luma gives other blobs than the frame itself is a conversion bug.
  return formats_ok ? 0 : 1;
}

int Main(int argc, char** argv) {
  try {
    const Args a = ParseArgs(argc, argv);
    if (!a.make_dir.empty()) {
      const uint64_t bytes = MakeFrames(a.make_dir, a.make);
      std::printf("wrote %u frames of %ux%u with %u markers to %s/cam1 (%.1f KiB per frame)\n",
                  a.make.count, a.make.width, a.make.height, a.make.markers, a.make_dir.c_str(),
                  bytes / 1024.0 / a.make.count);
      return 0;
    }
    return RunBench(a);
  } catch (const std::invalid_argument& e) {
    std::fprintf(stderr, "mocap-detect-bench: %s\n%s", e.what(), kUsage);
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "mocap-detect-bench: %s\n", e.what());
    return 1;
  }
}

}  // namespace
}  // namespace mocap

int main(int argc, char** argv) { return mocap::Main(argc, argv); }

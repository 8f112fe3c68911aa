#include "detect-bench/bench_formats.h"

#include <cstring>
#include <stdexcept>

#include "detect-bench/bench_timing.h"

extern "C" {
#include "capture/pixfmt.h"
#include <turbojpeg.h>

#include "capture/mjpeg.h"
}

namespace mocap {
namespace {

enum class Kind { kInPlace, kPacked, kMjpeg };

struct Format {
  const char* name;
  Kind kind;
  mn_pixfmt pixfmt;
  int bytes_per_pixel;  // packed formats
};

const Format kFormats[] = {
    {"GREY", Kind::kInPlace, MN_PIXFMT_Y16, 1},  {"NV12", Kind::kInPlace, MN_PIXFMT_Y16, 1},
    {"YU12", Kind::kInPlace, MN_PIXFMT_Y16, 1},  {"Y10", Kind::kPacked, MN_PIXFMT_Y10, 2},
    {"Y16", Kind::kPacked, MN_PIXFMT_Y16, 2},    {"YUYV", Kind::kPacked, MN_PIXFMT_YUYV, 2},
    {"UYVY", Kind::kPacked, MN_PIXFMT_UYVY, 2},  {"RGB3", Kind::kPacked, MN_PIXFMT_RGB24, 3},
    {"BGR3", Kind::kPacked, MN_PIXFMT_BGR24, 3}, {"BX24", Kind::kPacked, MN_PIXFMT_XRGB32, 4},
    {"XR24", Kind::kPacked, MN_PIXFMT_XBGR32, 4},
    {"MJPG", Kind::kMjpeg, MN_PIXFMT_Y16, 0},
};

// One frame as the camera would deliver it: the Y plane with neutral chroma after it, or each
// pixel's grey value in the packed layout.
std::vector<uint8_t> Pack(const Format& fmt, const BenchFrame& f) {
  const size_t n = static_cast<size_t>(f.width) * f.height;
  std::vector<uint8_t> out;
  if (fmt.kind == Kind::kInPlace) {
    out.assign(n + (fmt.name[0] == 'G' ? 0 : n / 2), 128);
    std::memcpy(out.data(), f.pixels.data(), n);
    return out;
  }
  out.resize(n * static_cast<size_t>(fmt.bytes_per_pixel));
  for (size_t i = 0; i < n; ++i) {
    const uint8_t v = f.pixels[i];
    uint8_t* p = out.data() + i * static_cast<size_t>(fmt.bytes_per_pixel);
    switch (fmt.pixfmt) {
      case MN_PIXFMT_Y10: p[0] = static_cast<uint8_t>(v << 2); p[1] = static_cast<uint8_t>(v >> 6); break;
      case MN_PIXFMT_Y16: p[0] = 0; p[1] = v; break;
      case MN_PIXFMT_YUYV: p[0] = v; p[1] = 128; break;
      case MN_PIXFMT_UYVY: p[0] = 128; p[1] = v; break;
      default: std::memset(p, v, static_cast<size_t>(fmt.bytes_per_pixel)); break;
    }
  }
  return out;
}

std::vector<uint8_t> PackMjpeg(const BenchFrame& f) {
  std::vector<uint8_t> rgb(static_cast<size_t>(f.width) * f.height * 3);
  for (size_t i = 0; i < f.pixels.size(); ++i) std::memset(&rgb[3 * i], f.pixels[i], 3);
  tjhandle tj = tjInitCompress();
  unsigned char* jpeg = nullptr;
  unsigned long size = 0;
  const int rc = tjCompress2(tj, rgb.data(), static_cast<int>(f.width), 0,
                             static_cast<int>(f.height), TJPF_RGB, &jpeg, &size, TJSAMP_422, 90, 0);
  tjDestroy(tj);
  if (rc != 0) throw std::runtime_error("cannot encode a JPEG frame");
  std::vector<uint8_t> out(jpeg, jpeg + size);
  tjFree(jpeg);
  return out;
}

bool SameBlobs(const mn_blob* a, size_t na, const std::vector<mn_blob>& b) {
  if (na != b.size()) return false;
  for (size_t i = 0; i < na; ++i)
    if (a[i].x != b[i].x || a[i].y != b[i].y || a[i].area != b[i].area) return false;
  return true;
}

}  // namespace

std::vector<FormatTiming> TimeFormats(const std::vector<BenchFrame>& frames, mn_detector* det,
                                      int repeat) {
  std::vector<mn_blob> blobs(65536);
  size_t n_blobs = 0;
  std::vector<std::vector<mn_blob>> original(frames.size());
  for (size_t i = 0; i < frames.size(); ++i) {
    const BenchFrame& f = frames[i];
    mn_detector_run(det, f.pixels.data(), f.width, f.height, f.width, blobs.data(), blobs.size(),
                    &n_blobs);
    original[i].assign(blobs.begin(), blobs.begin() + static_cast<long>(n_blobs));
  }
  mn_mjpeg* decoder = mn_mjpeg_new();
  if (decoder == nullptr) throw std::runtime_error("cannot make a JPEG decoder");
  std::vector<FormatTiming> out;
  for (const Format& fmt : kFormats) {
    std::vector<std::vector<uint8_t>> packed;
    for (const BenchFrame& f : frames) {
      if (fmt.kind == Kind::kMjpeg) {
        packed.push_back(PackMjpeg(f));
        continue;
      }
      packed.push_back(Pack(fmt, f));
    }
    std::vector<uint8_t> y8;
    size_t index = 0;
    // The node's step for this format: the luma of frame `index`.
    auto luma = [&](const BenchFrame& f) -> const uint8_t* {
      const std::vector<uint8_t>& src = packed[index];
      if (fmt.kind == Kind::kInPlace) return src.data();
      y8.resize(static_cast<size_t>(f.width) * f.height);
      if (fmt.kind == Kind::kMjpeg) {
        const char* why = nullptr;
        if (mn_mjpeg_to_y8(decoder, src.data(), src.size(), f.width, f.height, y8.data(),
                           f.width, &why) != 0)
          throw std::runtime_error(std::string("MJPEG frame does not decode: ") + why);
        return y8.data();
      }
      mn_pixfmt_to_y8(fmt.pixfmt, src.data(),
                      static_cast<size_t>(f.width) * static_cast<size_t>(fmt.bytes_per_pixel),
                      f.width, f.height, y8.data(), f.width);
      return y8.data();
    };
    FormatTiming t;
    t.name = fmt.name;
    t.lossless = fmt.kind != Kind::kMjpeg;
    for (index = 0; index < frames.size(); ++index) {
      const BenchFrame& f = frames[index];
      mn_detector_run(det, luma(f), f.width, f.height, f.width, blobs.data(), blobs.size(),
                      &n_blobs);
      if (t.lossless && !SameBlobs(blobs.data(), n_blobs, original[index])) t.same_blobs = false;
    }
    index = 0;
    volatile uintptr_t sink = 0;
    t.convert_ms = TimePerFrame(frames, repeat, [&](const BenchFrame& f) {
      sink = sink + reinterpret_cast<uintptr_t>(luma(f));
      index = (index + 1) % frames.size();
    });
    t.total_ms = TimePerFrame(frames, repeat, [&](const BenchFrame& f) {
      mn_detector_run(det, luma(f), f.width, f.height, f.width, blobs.data(), blobs.size(),
                      &n_blobs);
      index = (index + 1) % frames.size();
    });
    out.push_back(t);
  }
  mn_mjpeg_free(decoder);
  return out;
}

}  // namespace mocap

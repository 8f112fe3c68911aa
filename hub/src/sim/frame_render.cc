// Frame loop of `sim render`: the projector decides which markers each camera images (occlusion,
// image bounds, lens range) and where (distorted projection); the spot renderer draws them with
// their distance-dependent size and brightness over the frames-file background model, plus
// static reflections and flicker; the framefile writer stores only tiles that differ from it.
#include "sim/frame_render.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <memory>
#include <random>
#include <stdexcept>

#include "framefile/framefile.h"
#include "io/calibration_json.h"
#include "io/trc.h"
#include "io/visibility.h"
#include "sim/project_session.h"

namespace mocap {
namespace {

// Closes a frames-file writer that was not closed explicitly (an exception mid-render).
struct WriterCloser {
  void operator()(mn_ff_writer* writer) const { mn_ff_writer_close(writer); }
};
using WriterPtr = std::unique_ptr<mn_ff_writer, WriterCloser>;

struct CameraOutput {
  std::unique_ptr<SpotRenderer> renderer;
  WriterPtr writer;
  std::vector<Spot> reflections;
  std::mt19937_64 rng;  // flicker spots
  std::string dir;
};

}  // namespace

void FrameRenderOptions::Check() const {
  project.Check();
  render.Check();
  if (reflections < 0 || reflections > 1000) throw std::invalid_argument("--reflections must be 0..1000");
  if (!(flicker_spots >= 0.0 && flicker_spots <= 1000.0))
    throw std::invalid_argument("--flicker-spots must be 0..1000");
  if (!(blur_px >= 0.0 && blur_px <= 20.0)) throw std::invalid_argument("--blur-px must be 0..20");
  if (!(gain > 0.0 && gain <= 100.0)) throw std::invalid_argument("--gain must be in (0, 100]");
  if (zlib_level < 0 || zlib_level > 9) throw std::invalid_argument("--zlib-level must be 0..9");
}

std::string CameraFramesDir(const std::string& dir, uint32_t id) {
  return (std::filesystem::path(dir) / ("cam" + std::to_string(id))).string();
}

FrameRenderStats RenderFrames(const MarkerTrajectories& motion, const Rig& rig, const FrameRenderOptions& options,
                              const std::string& dir, const std::function<void(size_t, size_t)>& progress) {
  options.Check();
  if (!(motion.rate_hz > 0.0)) throw std::invalid_argument("motion rate must be positive");
  if (rig.cameras.empty()) throw std::invalid_argument("rig has no cameras");
  const uint32_t rate_mhz = static_cast<uint32_t>(std::llround(motion.rate_hz * 1000.0));

  std::filesystem::create_directories(dir);
  const std::filesystem::path root(dir);
  SaveRigJson(rig, (root / "calibration.json").string());
  WriteTrc(motion, (root / "truth.trc").string());
  VisibilityWriter visibility;
  visibility.Open((root / "visibility.tsv").string(), motion.names);

  std::vector<CameraOutput> cameras(rig.cameras.size());
  size_t max_pixels = 0;
  for (size_t i = 0; i < rig.cameras.size(); ++i) {
    const Camera& camera = rig.cameras[i];
    CameraOutput& out = cameras[i];
    SpotRenderOptions render = options.render;
    // Every camera has its own sensor noise and flicker, as real sensors do.
    render.noise_seed = options.render.noise_seed * 1000003u + camera.id;
    render.seed = options.render.seed * 1000003u + camera.id;
    const uint32_t width = static_cast<uint32_t>(camera.intrinsics.width);
    const uint32_t height = static_cast<uint32_t>(camera.intrinsics.height);
    out.renderer = std::make_unique<SpotRenderer>(render, width, height);
    out.dir = CameraFramesDir(dir, camera.id);
    const mn_ff_info info = out.renderer->FileInfo(rate_mhz);
    // Lossless: every pixel that differs from the background model is stored.
    const mn_ff_write_options write{options.zlib_level, -1};
    out.writer.reset(mn_ff_writer_open(out.dir.c_str(), &info, &write));
    if (!out.writer) throw std::runtime_error(out.dir + ": cannot write frames: " + std::strerror(errno));
    max_pixels = std::max(max_pixels, static_cast<size_t>(width) * height);

    std::seed_seq seq{static_cast<uint32_t>(options.project.seed), camera.id, 0x7e4du};
    out.rng.seed(seq);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    for (int r = 0; r < options.reflections; ++r) {
      out.reflections.push_back({unit(out.rng) * (width - 1), unit(out.rng) * (height - 1),
                                 0.8 + 1.7 * unit(out.rng), 120.0 + 120.0 * unit(out.rng)});
    }
  }

  FaultyProjector projector(rig, motion.NumMarkers(), options.project);
  std::vector<uint8_t> pixels(max_pixels);
  std::vector<Spot> spots;
  std::vector<int> cameras_seeing;
  FrameRenderStats stats;
  const size_t markers = motion.NumMarkers();
  for (size_t f = 0; f < motion.NumFrames(); ++f) {
    const uint64_t frame_number = motion.frame_numbers[f];
    const uint64_t trigger_ns =
        kSimEpochNs + static_cast<uint64_t>(std::llround(static_cast<double>(frame_number) * 1e9 / motion.rate_hz));
    const Eigen::Vector3d* points = markers > 0 ? &motion.points[f * markers] : nullptr;
    cameras_seeing.assign(markers, 0);
    for (size_t i = 0; i < rig.cameras.size(); ++i) {
      CameraOutput& out = cameras[i];
      const Camera& camera = rig.cameras[i];
      spots = out.reflections;
      for (const FaultyProjector::MarkerImage& image : projector.ImageMarkers(i, points)) {
        ++cameras_seeing[image.marker];
        // The renderer draws a Gaussian of sigma = radius / 2 (the disc's second moments); the
        // blur adds its variance.
        const double radius = std::sqrt(image.radius * image.radius + 4.0 * options.blur_px * options.blur_px);
        spots.push_back({image.pixel.x(), image.pixel.y(), radius, options.gain * FaultyProjector::MarkerPeak(image.depth)});
      }
      if (options.flicker_spots > 0.0) {
        std::uniform_real_distribution<double> unit(0.0, 1.0);
        const int count = std::poisson_distribution<int>(options.flicker_spots)(out.rng);
        for (int k = 0; k < count; ++k) {
          spots.push_back({unit(out.rng) * (camera.intrinsics.width - 1), unit(out.rng) * (camera.intrinsics.height - 1),
                           0.6 + 1.4 * unit(out.rng), 80.0 + 160.0 * unit(out.rng)});
        }
      }
      stats.spots += spots.size();
      const size_t stride = static_cast<size_t>(camera.intrinsics.width);
      out.renderer->Render(frame_number, spots, pixels.data(), stride);
      if (mn_ff_writer_add(out.writer.get(), frame_number, trigger_ns, pixels.data(), stride) < 0)
        throw std::runtime_error(out.dir + ": cannot write frame: " + std::strerror(errno));
      ++stats.camera_frames;
    }
    for (size_t m = 0; m < markers; ++m) {
      if (!motion.Has(f, m)) continue;
      ++stats.present;
      stats.reconstructible += cameras_seeing[m] >= 2 ? 1 : 0;
    }
    visibility.WriteFrame(frame_number, cameras_seeing);
    ++stats.frames;
    if (progress) progress(f + 1, motion.NumFrames());
  }
  visibility.Close();
  for (CameraOutput& out : cameras) {
    stats.bytes += mn_ff_writer_bytes(out.writer.get());
    if (mn_ff_writer_close(out.writer.release()) < 0)
      throw std::runtime_error(out.dir + ": cannot finish frames file: " + std::strerror(errno));
  }
  return stats;
}

}  // namespace mocap

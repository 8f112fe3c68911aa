// Synthetic frames: markers with random sizes and brightness drift across the image at a few
// pixels per frame and bounce off its edges; frames are written losslessly (only tiles that
// differ from the background model are stored).
#include "detect-bench/make_frames.h"

#include <cerrno>
#include <cstring>
#include <random>
#include <stdexcept>
#include <vector>

#include "framefile/framefile.h"
#include "sim/spot_render.h"

namespace mocap {

uint64_t MakeFrames(const std::string& dir, const MakeFramesOptions& o) {
  if (o.count < 1 || o.count > 100000) throw std::invalid_argument("--count must be 1..100000");
  if (o.markers > 100000) throw std::invalid_argument("--markers must be 0..100000");
  if (o.width < 16 || o.height < 16 || o.width > MN_FF_MAX_SIDE || o.height > MN_FF_MAX_SIDE)
    throw std::invalid_argument("--width/--height must be 16..16384");

  SpotRenderOptions ro;
  ro.background = 12;
  ro.noise_sigma = 1.5;
  ro.noise_seed = o.seed;
  ro.seed = o.seed + 1;
  ro.shot_noise = 0.3;
  SpotRenderer renderer(ro, o.width, o.height);

  std::mt19937_64 rng(o.seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  struct Marker {
    Spot spot;
    double vx, vy;
  };
  std::vector<Marker> markers(o.markers);
  for (Marker& m : markers) {
    m.spot.x = 8.0 + u(rng) * (o.width - 16.0);
    m.spot.y = 8.0 + u(rng) * (o.height - 16.0);
    m.spot.radius_px = 2.0 + 3.0 * u(rng);
    m.spot.peak = 160.0 + 80.0 * u(rng);
    m.vx = 6.0 * u(rng) - 3.0;
    m.vy = 6.0 * u(rng) - 3.0;
  }

  const std::string cam = dir + "/cam1";
  const mn_ff_info info = renderer.FileInfo(120000);
  const mn_ff_write_options wo = {1, -1};
  mn_ff_writer* wr = mn_ff_writer_open(cam.c_str(), &info, &wo);
  if (!wr) throw std::runtime_error("cannot write " + cam + ": " + std::strerror(errno));
  std::vector<uint8_t> px(static_cast<size_t>(o.width) * o.height);
  std::vector<Spot> spots(markers.size());
  for (uint32_t f = 0; f < o.count; ++f) {
    for (size_t i = 0; i < markers.size(); ++i) spots[i] = markers[i].spot;
    renderer.Render(f, spots, px.data(), o.width);
    if (mn_ff_writer_add(wr, f, f * 8333333ull, px.data(), o.width) != 0) {
      const int e = errno;
      mn_ff_writer_close(wr);
      throw std::runtime_error("writing " + cam + ": " + std::strerror(e));
    }
    for (Marker& m : markers) {
      m.spot.x += m.vx;
      m.spot.y += m.vy;
      if (m.spot.x < 4.0 || m.spot.x > o.width - 5.0) m.vx = -m.vx;
      if (m.spot.y < 4.0 || m.spot.y > o.height - 5.0) m.vy = -m.vy;
    }
  }
  const uint64_t bytes = mn_ff_writer_bytes(wr);
  if (mn_ff_writer_close(wr) != 0)
    throw std::runtime_error("closing " + cam + ": " + std::strerror(errno));
  return bytes;
}

}  // namespace mocap

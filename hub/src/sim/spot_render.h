// Renders marker spots (sub-pixel centre, radius, peak) onto Y8 frames over the background-
// and-noise model of the recorded-frame format (firmware/framefile), so `sim render` output
// stores only the tiles that hold spots. Intensities are integrated over each pixel's area.
#pragma once

#include <cstddef>
#include <cstdint>
#include <random>
#include <vector>

#include "framefile/framefile.h"

namespace mocap {

// One spot in image coordinates (pixel centres at integers, as the detector reports them).
struct Spot {
  double x = 0.0, y = 0.0;
  // Radius of the marker's disc image in pixels. The spot is drawn as a Gaussian with the
  // disc's second moments (sigma = radius / 2), so its edge is smooth like a real lens's.
  double radius_px = 2.0;
  double peak = 200.0;  // brightness above the background at the centre, grey levels
};

struct SpotRenderOptions {
  int background = 12;         // background grey level
  double noise_sigma = 1.5;    // background noise sigma, grey levels (0..64)
  uint64_t noise_seed = 1;     // seeds the background model (stored in the frames file)
  double flicker = 0.0;        // each spot's brightness varies by up to this fraction per frame
  double shot_noise = 0.0;     // extra noise on spot pixels: sigma = shot_noise * sqrt(signal)
  uint64_t seed = 1;           // seeds flicker and shot noise

  // Throws std::invalid_argument naming the bad option.
  void Check() const;
};

class SpotRenderer {
 public:
  // Throws std::invalid_argument for bad options or a size outside 1..16384.
  SpotRenderer(const SpotRenderOptions& options, uint32_t width, uint32_t height);
  ~SpotRenderer();
  SpotRenderer(const SpotRenderer&) = delete;
  SpotRenderer& operator=(const SpotRenderer&) = delete;

  // Draws frame `frame_number` into pixels (width x height, stride bytes per row): the
  // background model of that frame, then the spots. Spots partly outside are clipped; the
  // result is deterministic in (options, frame_number, spots).
  void Render(uint64_t frame_number, const std::vector<Spot>& spots, uint8_t* pixels,
              size_t stride);

  // Header fields for a frames file whose background model matches this renderer's.
  mn_ff_info FileInfo(uint32_t rate_mhz) const;

 private:
  SpotRenderOptions options_;
  uint32_t width_, height_;
  mn_ff_noise* noise_ = nullptr;
  std::vector<float> signal_;  // spot light per pixel, zero outside the current frame's spots
  std::vector<double> gx_, gy_;
};

}  // namespace mocap

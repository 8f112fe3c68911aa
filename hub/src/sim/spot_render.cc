// Spot rendering: each spot's Gaussian is integrated exactly over pixel squares with erf
// (separable), summed in float so overlapping spots add before rounding, then added to the
// frames-file background model and quantised once per pixel.
#include "sim/spot_render.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace mocap {

void SpotRenderOptions::Check() const {
  if (background < 0 || background > 255)
    throw std::invalid_argument("background must be 0..255");
  if (!(noise_sigma >= 0.0 && noise_sigma <= 64.0))
    throw std::invalid_argument("noise sigma must be 0..64 grey levels");
  if (!(flicker >= 0.0 && flicker < 1.0))
    throw std::invalid_argument("flicker must be in [0, 1)");
  if (!(shot_noise >= 0.0 && shot_noise <= 10.0))
    throw std::invalid_argument("shot noise must be 0..10");
}

SpotRenderer::SpotRenderer(const SpotRenderOptions& options, uint32_t width, uint32_t height)
    : options_(options), width_(width), height_(height) {
  options_.Check();
  if (width < 1 || height < 1 || width > MN_FF_MAX_SIDE || height > MN_FF_MAX_SIDE)
    throw std::invalid_argument("frame size must be 1..16384 pixels per side");
  noise_ = mn_ff_noise_new(width, static_cast<uint8_t>(options_.background),
                           FileInfo(0).noise_sigma_q8, options_.noise_seed);
  if (!noise_) throw std::runtime_error("out of memory for the background model");
  signal_.assign(static_cast<size_t>(width) * height, 0.0f);
}

SpotRenderer::~SpotRenderer() { mn_ff_noise_free(noise_); }

mn_ff_info SpotRenderer::FileInfo(uint32_t rate_mhz) const {
  mn_ff_info info{};
  info.width = width_;
  info.height = height_;
  info.rate_mhz = rate_mhz;
  info.background = static_cast<uint8_t>(options_.background);
  info.noise_sigma_q8 = static_cast<uint32_t>(std::lround(options_.noise_sigma * 256.0));
  info.noise_seed = options_.noise_seed;
  return info;
}

namespace {

// Integral of exp(-u^2 / (2 s^2)) over [a, b].
double GaussIntegral(double a, double b, double sigma) {
  const double k = 1.0 / (sigma * std::sqrt(2.0));
  constexpr double kPi = 3.14159265358979323846;
  return sigma * std::sqrt(kPi / 2.0) * (std::erf(b * k) - std::erf(a * k));
}

}  // namespace

void SpotRenderer::Render(uint64_t frame_number, const std::vector<Spot>& spots,
                          uint8_t* pixels, size_t stride) {
  if (stride < width_) throw std::invalid_argument("stride smaller than the frame width");
  mn_ff_noise_fill(noise_, frame_number, 0, 0, width_, height_, pixels, stride);

  // Per-frame generator: the same frame renders the same whatever was rendered before.
  std::mt19937_64 rng(options_.seed * 0x9e3779b97f4a7c15ull + frame_number);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::normal_distribution<double> normal(0.0, 1.0);

  // Bounding rows/columns of everything drawn, so only that area is quantised and cleared.
  int64_t x_lo = width_, x_hi = -1, y_lo = height_, y_hi = -1;
  for (const Spot& s : spots) {
    if (!std::isfinite(s.x) || !std::isfinite(s.y) || !(s.radius_px > 0.0) || !(s.peak > 0.0))
      continue;
    double peak = s.peak;
    if (options_.flicker > 0.0) peak *= 1.0 - options_.flicker * unit(rng);
    const double sigma = std::max(0.5, s.radius_px / 2.0);
    const double reach = 4.5 * sigma + 1.0;  // beyond this the light is below 1e-4 of the peak
    int64_t x0 = std::max<int64_t>(0, static_cast<int64_t>(std::floor(s.x - reach)));
    int64_t x1 = std::min<int64_t>(width_ - 1, static_cast<int64_t>(std::ceil(s.x + reach)));
    int64_t y0 = std::max<int64_t>(0, static_cast<int64_t>(std::floor(s.y - reach)));
    int64_t y1 = std::min<int64_t>(height_ - 1, static_cast<int64_t>(std::ceil(s.y + reach)));
    if (x0 > x1 || y0 > y1) continue;  // entirely outside the frame
    gx_.resize(static_cast<size_t>(x1 - x0 + 1));
    gy_.resize(static_cast<size_t>(y1 - y0 + 1));
    // Mean of the unit-peak profile over each pixel: the pixel's share of the light.
    for (int64_t x = x0; x <= x1; ++x)
      gx_[x - x0] = GaussIntegral(x - 0.5 - s.x, x + 0.5 - s.x, sigma);
    for (int64_t y = y0; y <= y1; ++y)
      gy_[y - y0] = GaussIntegral(y - 0.5 - s.y, y + 0.5 - s.y, sigma);
    for (int64_t y = y0; y <= y1; ++y) {
      float* row = &signal_[static_cast<size_t>(y) * width_];
      const double py = peak * gy_[y - y0];
      for (int64_t x = x0; x <= x1; ++x) row[x] += static_cast<float>(py * gx_[x - x0]);
    }
    x_lo = std::min(x_lo, x0);
    x_hi = std::max(x_hi, x1);
    y_lo = std::min(y_lo, y0);
    y_hi = std::max(y_hi, y1);
  }

  for (int64_t y = y_lo; y <= y_hi; ++y) {
    float* row = &signal_[static_cast<size_t>(y) * width_];
    uint8_t* out = pixels + static_cast<size_t>(y) * stride;
    for (int64_t x = x_lo; x <= x_hi; ++x) {
      if (row[x] == 0.0f) continue;
      double v = out[x] + static_cast<double>(row[x]);
      if (options_.shot_noise > 0.0)
        v += options_.shot_noise * std::sqrt(static_cast<double>(row[x])) * normal(rng);
      out[x] = static_cast<uint8_t>(std::clamp(std::lround(v), 0L, 255L));
      row[x] = 0.0f;
    }
  }
}

}  // namespace mocap

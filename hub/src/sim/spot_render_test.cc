// Spot renderer tests: the rendered spot's intensity-weighted centroid (background model
// subtracted) equals its centre, overlapping/clipped/outside spots, flicker, determinism and
// option checking.
#include "sim/spot_render.h"

#include <gtest/gtest.h>

#include "detect/detect.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>
#include <vector>

namespace mocap {
namespace {

constexpr uint32_t kW = 200, kH = 120;

struct Centroid {
  double x = 0, y = 0, flux = 0;
};

// Weighted centroid of (frame - model) in a window around (cx, cy).
Centroid Measure(const std::vector<uint8_t>& frame, const std::vector<uint8_t>& model, double cx,
                 double cy, int reach) {
  Centroid c;
  for (int y = static_cast<int>(cy) - reach; y <= static_cast<int>(cy) + reach; ++y) {
    for (int x = static_cast<int>(cx) - reach; x <= static_cast<int>(cx) + reach; ++x) {
      if (x < 0 || y < 0 || x >= static_cast<int>(kW) || y >= static_cast<int>(kH)) continue;
      const double w = static_cast<double>(frame[y * kW + x]) - model[y * kW + x];
      c.x += w * x;
      c.y += w * y;
      c.flux += w;
    }
  }
  c.x /= c.flux;
  c.y /= c.flux;
  return c;
}

std::vector<uint8_t> Render(SpotRenderer& r, uint64_t frame, const std::vector<Spot>& spots) {
  std::vector<uint8_t> px(kW * kH);
  r.Render(frame, spots, px.data(), kW);
  return px;
}

// Rounding to 8 bits moves a spot's centroid by up to ~0.01 px (more once the top clips), so
// the check is on each spot's error and on their RMS, which exact integration keeps small.
void CheckCentroids(const SpotRenderOptions& opts, double peak, double tolerance,
                    double rms_tolerance) {
  SpotRenderer r(opts, kW, kH);
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> sub(0.0, 1.0);
  std::vector<Spot> spots;
  for (int i = 0; i < 12; ++i) {
    Spot s;
    s.x = 20 + 30 * (i % 6) + sub(rng);
    s.y = 30 + 60 * (i / 6) + sub(rng);
    s.radius_px = 1.0 + 0.4 * i;
    s.peak = peak;
    spots.push_back(s);
  }
  const auto model = Render(r, 9, {});
  const auto frame = Render(r, 9, spots);
  double sum_sq = 0.0;
  for (const Spot& s : spots) {
    const Centroid c = Measure(frame, model, s.x, s.y, 14);
    EXPECT_NEAR(c.x, s.x, tolerance) << "radius " << s.radius_px;
    EXPECT_NEAR(c.y, s.y, tolerance) << "radius " << s.radius_px;
    EXPECT_GT(c.flux, 0.0);
    sum_sq += (c.x - s.x) * (c.x - s.x) + (c.y - s.y) * (c.y - s.y);
  }
  EXPECT_LT(std::sqrt(sum_sq / (2.0 * spots.size())), rms_tolerance);
}

TEST(SpotRender, CentroidIsCentreWithoutNoise) {
  SpotRenderOptions opts;
  opts.noise_sigma = 0.0;
  CheckCentroids(opts, 180.0, 0.015, 0.007);
}

TEST(SpotRender, CentroidIsCentreOverNoisyBackground) {
  SpotRenderOptions opts;
  opts.noise_sigma = 2.0;
  CheckCentroids(opts, 180.0, 0.015, 0.007);
}

TEST(SpotRender, SaturatedSpotsStaySymmetric) {
  SpotRenderOptions opts;
  opts.noise_sigma = 0.0;
  CheckCentroids(opts, 600.0, 0.03, 0.015);
  SpotRenderer r(opts, kW, kH);
  const auto frame = Render(r, 0, {{50.3, 50.6, 4.0, 600.0}});
  EXPECT_EQ(frame[50 * kW + 50], 255);
}

TEST(SpotRender, SpotLightIsItsPeakTimesArea) {
  // Total light of a Gaussian with peak P and sigma s is 2 pi s^2 P.
  SpotRenderOptions opts;
  opts.noise_sigma = 0.0;
  SpotRenderer r(opts, kW, kH);
  const auto model = Render(r, 1, {});
  const auto frame = Render(r, 1, {{100.25, 60.75, 6.0, 100.0}});
  const Centroid c = Measure(frame, model, 100.25, 60.75, 20);
  EXPECT_NEAR(c.flux, 2.0 * M_PI * 9.0 * 100.0, 2.0 * M_PI * 9.0 * 100.0 * 0.01);
  EXPECT_NEAR(frame[60 * kW + 100] - model[60 * kW + 100], 100.0 * 0.97, 3.0);
}

TEST(SpotRender, OnlyPixelsNearSpotsChange) {
  SpotRenderOptions opts;
  SpotRenderer r(opts, kW, kH);
  const auto model = Render(r, 4, {});
  // A spot fully outside the frame changes nothing; one on the edge is clipped safely.
  EXPECT_EQ(Render(r, 4, {{-50.0, 10.0, 3.0, 200.0}, {kW + 40.0, 10.0, 3.0, 200.0}}), model);
  const auto frame = Render(r, 4, {{0.0, 0.0, 3.0, 200.0}, {150.0, 80.0, 2.0, 200.0}});
  for (uint32_t y = 0; y < kH; ++y) {
    for (uint32_t x = 0; x < kW; ++x) {
      const bool near = std::hypot(x - 0.0, y - 0.0) < 9 || std::hypot(x - 150.0, y - 80.0) < 7;
      if (!near) {
        ASSERT_EQ(frame[y * kW + x], model[y * kW + x]) << x << "," << y;
      }
    }
  }
  EXPECT_GT(frame[0], 150);
  // NaN or non-positive spots are skipped.
  EXPECT_EQ(Render(r, 4, {{NAN, 5.0, 3.0, 200.0}, {5.0, 5.0, 0.0, 200.0}}), model);
}

TEST(SpotRender, OverlappingSpotsAdd) {
  SpotRenderOptions opts;
  opts.noise_sigma = 0.0;
  SpotRenderer r(opts, kW, kH);
  const auto model = Render(r, 2, {});
  const auto one = Render(r, 2, {{80.0, 60.0, 3.0, 60.0}});
  const auto two = Render(r, 2, {{80.0, 60.0, 3.0, 60.0}, {80.0, 60.0, 3.0, 60.0}});
  EXPECT_NEAR(two[60 * kW + 80] - model[60 * kW + 80], 2.0 * (one[60 * kW + 80] - model[60 * kW + 80]),
              1.0);
}

TEST(SpotRender, DeterministicAndFlickering) {
  SpotRenderOptions opts;
  opts.flicker = 0.5;
  opts.shot_noise = 0.5;
  SpotRenderer a(opts, kW, kH), b(opts, kW, kH);
  const std::vector<Spot> spots = {{60.4, 40.2, 3.0, 150.0}};
  EXPECT_EQ(Render(a, 17, spots), Render(b, 17, spots));
  double lo = 1e9, hi = 0;
  for (uint64_t f = 0; f < 40; ++f) {
    const auto model_f = Render(a, f, {});
    const double flux = Measure(Render(a, f, spots), model_f, 60.4, 40.2, 12).flux;
    lo = std::min(lo, flux);
    hi = std::max(hi, flux);
  }
  const double full = 2.0 * M_PI * 2.25 * 150.0;
  EXPECT_GT(lo, 0.45 * full);
  EXPECT_LT(hi, 1.05 * full);
  EXPECT_GT(hi - lo, 0.2 * full);
}

TEST(SpotRender, FileInfoMatchesBackgroundModel) {
  SpotRenderOptions opts;
  opts.background = 20;
  opts.noise_sigma = 1.25;
  opts.noise_seed = 99;
  SpotRenderer r(opts, kW, kH);
  const mn_ff_info info = r.FileInfo(120000);
  EXPECT_EQ(info.background, 20);
  EXPECT_EQ(info.noise_sigma_q8, 320u);
  EXPECT_EQ(info.noise_seed, 99u);
  EXPECT_EQ(info.rate_mhz, 120000u);
  mn_ff_noise* noise = mn_ff_noise_new(kW, 20, 320, 99);
  std::vector<uint8_t> model(kW * kH);
  mn_ff_noise_fill(noise, 5, 0, 0, kW, kH, model.data(), kW);
  mn_ff_noise_free(noise);
  EXPECT_EQ(Render(r, 5, {}), model);
}

// End to end with the node's detector: rendered markers are found where they were drawn.
TEST(SpotRender, DetectorFindsRenderedSpots) {
  SpotRenderOptions opts;
  opts.noise_sigma = 1.5;
  SpotRenderer r(opts, kW, kH);
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<Spot> spots;
  for (int i = 0; i < 18; ++i)
    spots.push_back({15.0 + 30.0 * (i % 6) + u(rng), 20.0 + 40.0 * (i / 6) + u(rng),
                     2.5 + 2.5 * u(rng), 180.0 + 60.0 * u(rng)});
  const auto frame = Render(r, 3, spots);

  mn_detect_config cfg;
  mn_detect_config_default(&cfg);
  cfg.threshold = 40;
  mn_detector* det = mn_detector_new(&cfg, kW, kH);
  ASSERT_NE(det, nullptr);
  std::vector<mn_blob> blobs(64);
  size_t n = 0;
  ASSERT_EQ(mn_detector_run(det, frame.data(), kW, kH, kW, blobs.data(), blobs.size(), &n), 0);
  mn_detector_free(det);
  ASSERT_EQ(n, spots.size());
  double worst = 0.0;
  for (const Spot& s : spots) {
    double best = 1e9;
    for (size_t i = 0; i < n; ++i) best = std::min(best, std::hypot(blobs[i].x - s.x, blobs[i].y - s.y));
    worst = std::max(worst, best);
  }
  EXPECT_LT(worst, 0.03);
}

TEST(SpotRender, RejectsBadOptions) {
  SpotRenderOptions opts;
  opts.flicker = 1.0;
  EXPECT_THROW(opts.Check(), std::invalid_argument);
  opts = SpotRenderOptions();
  opts.noise_sigma = -1.0;
  EXPECT_THROW(SpotRenderer(opts, kW, kH), std::invalid_argument);
  opts = SpotRenderOptions();
  opts.background = 300;
  EXPECT_THROW(opts.Check(), std::invalid_argument);
  EXPECT_THROW(SpotRenderer(SpotRenderOptions(), 0, 10), std::invalid_argument);
  SpotRenderer r(SpotRenderOptions(), kW, kH);
  std::vector<uint8_t> px(kW * kH);
  EXPECT_THROW(r.Render(0, {}, px.data(), kW - 1), std::invalid_argument);
}

}  // namespace
}  // namespace mocap

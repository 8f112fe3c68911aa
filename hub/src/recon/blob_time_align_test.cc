#include "recon/blob_time_align.h"

#include <cmath>
#include <random>

#include <gtest/gtest.h>

namespace mocap {
namespace {

constexpr double kRate = 30.0;
constexpr uint64_t kEpoch = 1700000000000000000ull;

// One camera's frame at slot n: blobs moving at `velocity` px/s, exposed `offset_s` after the
// slot's instant, stamped `stamp_error_s` off.
CameraFrame MovingBlobs(uint32_t camera, uint64_t n, double offset_s, double stamp_error_s,
                        const std::vector<Eigen::Vector2d>& starts, const Eigen::Vector2d& velocity) {
  CameraFrame frame;
  frame.camera_id = camera;
  frame.frame_number = n;
  const double t = static_cast<double>(n) / kRate + offset_s;
  frame.capture_time_ns = kEpoch + static_cast<uint64_t>(std::llround((t + stamp_error_s) * 1e9));
  for (const Eigen::Vector2d& start : starts) {
    Blob blob;
    blob.pixel = start + velocity * t;
    frame.blobs.push_back(blob);
  }
  return frame;
}

BlobTimeAlignOptions Options() {
  BlobTimeAlignOptions options;
  options.rate_hz = kRate;
  options.epoch_ns = kEpoch;
  return options;
}

TEST(BlobTimeAlign, BringsBlobsToTheSetInstant) {
  BlobTimeAligner aligner(Options());
  const std::vector<Eigen::Vector2d> starts = {{100, 100}, {300, 120}, {500, 400}};
  const Eigen::Vector2d velocity(120.0, -60.0);  // 4 px and 2 px per frame
  const double offset = 0.4 / kRate;              // 13 ms late
  for (uint64_t n = 10; n < 20; ++n) {
    FrameSet set;
    set.frame_number = n;
    set.cameras.push_back(MovingBlobs(1, n, offset, 0.0, starts, velocity));
    aligner.Align(&set);
    for (size_t b = 0; b < starts.size(); ++b) {
      const Eigen::Vector2d at_instant = starts[b] + velocity * (static_cast<double>(n) / kRate);
      const double error = (set.cameras[0].blobs[b].pixel - at_instant).norm();
      if (n <= 11)
        EXPECT_NEAR(error, velocity.norm() * offset, 1e-6) << "no confirmed track yet: left as captured";
      else
        EXPECT_LT(error, 1e-6) << "frame " << n << " blob " << b;
    }
  }
  EXPECT_NEAR(aligner.OffsetS(1), offset, 1e-9);
  EXPECT_EQ(aligner.stats().blobs_kept, 6u);
  EXPECT_EQ(aligner.stats().blobs_moved, 24u);
}

TEST(BlobTimeAlign, AveragesTheStampsJitter) {
  BlobTimeAligner aligner(Options());
  std::mt19937_64 rng(7);
  std::normal_distribution<double> jitter(0.0, 1e-3);
  const std::vector<Eigen::Vector2d> starts = {{200, 200}};
  const Eigen::Vector2d velocity(300.0, 0.0);  // 10 px per frame
  const double offset = -0.3 / kRate;
  double sum_sq = 0.0, raw_sq = 0.0;
  int counted = 0;
  for (uint64_t n = 0; n < 300; ++n) {
    FrameSet set;
    set.frame_number = n;
    set.cameras.push_back(MovingBlobs(2, n, offset, jitter(rng), starts, velocity));
    const Eigen::Vector2d captured = set.cameras[0].blobs[0].pixel;
    aligner.Align(&set);
    if (n < 100) continue;  // the average settles
    const Eigen::Vector2d at_instant = starts[0] + velocity * (static_cast<double>(n) / kRate);
    sum_sq += (set.cameras[0].blobs[0].pixel - at_instant).squaredNorm();
    raw_sq += (captured - at_instant).squaredNorm();
    ++counted;
  }
  const double rms = std::sqrt(sum_sq / counted);
  // Using each stamp as it came would leave 300 px/s x 1 ms = 0.3 px; the average does better.
  EXPECT_LT(rms, 0.15);
  EXPECT_GT(std::sqrt(raw_sq / counted), 2.9);  // 10 px/frame x 0.3 frame as captured
}

TEST(BlobTimeAlign, LeavesUnpairedBlobsAndRestartsAfterAGap) {
  BlobTimeAlignOptions options = Options();
  options.max_step_px = 5.0;
  BlobTimeAligner aligner(options);
  const Eigen::Vector2d velocity(60.0, 0.0);  // 2 px per frame
  const double offset = 0.5 / kRate;
  FrameSet set;
  set.frame_number = 1;
  set.cameras.push_back(MovingBlobs(3, 1, offset, 0.0, {{100, 100}}, velocity));
  aligner.Align(&set);
  set.frame_number = 2;
  set.cameras = {MovingBlobs(3, 2, offset, 0.0, {{100, 100}}, velocity)};
  aligner.Align(&set);
  // A blob further than the step from every blob of the previous frame stays as captured.
  set.frame_number = 3;
  set.cameras = {MovingBlobs(3, 3, offset, 0.0, {{100, 100}, {400, 100}}, velocity)};
  const Eigen::Vector2d far = set.cameras[0].blobs[1].pixel;
  aligner.Align(&set);
  EXPECT_EQ(set.cameras[0].blobs[1].pixel, far);
  EXPECT_EQ(aligner.stats().blobs_moved, 1u);
  // After more than max_gap_frames the previous frame gives no velocity.
  set.frame_number = 9;
  set.cameras = {MovingBlobs(3, 9, offset, 0.0, {{100, 100}}, velocity)};
  const Eigen::Vector2d captured = set.cameras[0].blobs[0].pixel;
  aligner.Align(&set);
  EXPECT_EQ(set.cameras[0].blobs[0].pixel, captured);
  EXPECT_EQ(aligner.stats().blobs_moved, 1u);
}

TEST(BlobTimeAlign, NeverMovesABlobAlongItsNeighboursStep) {
  // Two markers 6 px apart moving 10 px per frame along their line: each blob's nearest blob in
  // the previous frame is the other marker's, so every pairing within a step crosses and no
  // prediction confirms it. The blobs stay as captured rather than move along a wrong step.
  BlobTimeAligner aligner(Options());
  const std::vector<Eigen::Vector2d> starts = {{100, 200}, {106, 200}};
  const Eigen::Vector2d velocity(300.0, 0.0);
  const double offset = -0.45 / kRate;
  for (uint64_t n = 0; n < 12; ++n) {
    FrameSet set;
    set.frame_number = n;
    set.cameras.push_back(MovingBlobs(4, n, offset, 0.0, starts, velocity));
    const FrameSet captured = set;
    aligner.Align(&set);
    for (size_t b = 0; b < starts.size(); ++b)
      EXPECT_EQ(set.cameras[0].blobs[b].pixel, captured.cameras[0].blobs[b].pixel) << "frame " << n;
  }
  EXPECT_EQ(aligner.stats().blobs_moved, 0u);
}

TEST(BlobTimeAlign, RefusesBadOptions) {
  BlobTimeAlignOptions options = Options();
  options.rate_hz = 0.0;
  EXPECT_THROW(options.Check(), std::invalid_argument);
  options = Options();
  options.max_step_px = -1.0;
  EXPECT_THROW(options.Check(), std::invalid_argument);
  options = Options();
  options.offset_weight = 1.5;
  EXPECT_THROW(options.Check(), std::invalid_argument);
  options = Options();
  options.max_gap_frames = 0;
  EXPECT_THROW(options.Check(), std::invalid_argument);
  options = Options();
  options.predicted_gate_px = options.max_step_px + 1.0;
  EXPECT_THROW(options.Check(), std::invalid_argument);
}

}  // namespace
}  // namespace mocap

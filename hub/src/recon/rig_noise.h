// The rig's centroid noise and the gates that follow from it. A machine-vision camera's blob
// centroids are good to 0.05-0.2 px, a webcam's to 1-2 px: one set of pixel and millimetre gates
// cannot serve both. The noise comes from the calibration (each camera's centroid_rms_px, the
// wand solve's residuals), is then measured from the reconstruction's own residuals, and every
// gate is widened to follow it. The configured gates are floors: on a rig at least as precise as
// the one they were tuned on (0.2 px) nothing changes.
#pragma once

#include <vector>

#include "geometry/camera.h"
#include "recon/recon_options.h"
#include "recon/triangulation.h"

namespace mocap {

// How many noise sigmas (per image axis) each gate spans.
struct NoiseGateFactors {
  // A view's reprojection error length: P(error > 4 sigma) = exp(-8) for a 2-D Gaussian.
  static constexpr double kReprojectionSigmas = 4.0;
  // Two rays' distance, in sigmas of one view's lateral error at the volume (two views'
  // errors add: 3.5 sigmas of their difference).
  static constexpr double kRaySigmas = 5.0;
  // A prediction's smallest search radius in an image.
  static constexpr double kPredictionGateSigmas = 4.0;
  // The tracker's smallest gate, in sigmas of a point's error (mm).
  static constexpr double kTrackerGateSigmas = 6.0;
};

// Millimetres per pixel at the working volume: the median over cameras of the distance from the
// camera centre to the point nearest every optical axis, over the focal length. The scale that
// turns a centroid noise into a ray distance or a point's error.
double RigMmPerPx(const Rig& rig);

// The calibration's centroid noise sigma per image axis (px): the RMS of the cameras' known
// centroid_rms_px (a residual length, sqrt(2) sigmas) over sqrt(2); 0 when no camera has one.
double CalibratedNoisePx(const Rig& rig);

// The reconstruction options with every pixel and millimetre gate widened to follow a centroid
// noise sigma_px (per axis) on a rig of mm_per_px: reprojection and merged-blob limits, the
// epipolar graph's and the clustering matcher's ray distances, the prediction search's smallest
// radius. A gate is never narrowed below its configured value; the merged-blob limit is at least
// the reprojection limit it then follows.
ReconstructorOptions GatesForNoise(const ReconstructorOptions& configured, double sigma_px, double mm_per_px);

// Measures the centroid noise from triangulated points: a point of n views whose residuals'
// squares sum to S has 2n - 3 degrees of freedom, so S / (2n - 3) estimates sigma^2. A frame's
// estimate is the lower quartile over its points of that ratio over the chi-square lower
// quartile for its degrees of freedom (wrong matches, merged blobs and gates still too tight
// all act on the upper part; with the median, wrong matches in gates opened by them ran away to
// 11 px on seed 001's 2 px protocol); frames are averaged with
// a weight that starts at the first frame's and settles at 1 / kSettleFrames, so a rig noisier
// than the gates it starts with opens them within a few dozen frames.
class CentroidNoiseMeter {
 public:
  static constexpr int kSettleFrames = 20;
  static constexpr int kMinPoints = 3;  // fewer points in a frame say nothing
  // prior_px: the noise to start from (the calibration's), 0 when unknown.
  explicit CentroidNoiseMeter(double prior_px = 0.0);

  void AddFrame(const std::vector<TriangulatedPoint>& points);
  // Current estimate (px, per image axis): the prior until a frame was measured.
  double sigma_px() const;
  long long frames_measured() const { return frames_; }

 private:
  double variance_ = 0.0;
  long long frames_ = 0;
  std::vector<double> scratch_;
};

}  // namespace mocap

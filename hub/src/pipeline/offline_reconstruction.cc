// Offline reconstruction of a session (see offline_reconstruction.h).
#include "pipeline/offline_reconstruction.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace mocap::pipeline {
namespace {

OfflineReconstructionOptions AtRate(OfflineReconstructionOptions options, double rate_hz) {
  options.tracker.rate_hz = rate_hz;
  options.gap_fill.max_spline_gap = static_cast<int>(std::lround(options.max_spline_gap_s * rate_hz));
  options.gap_fill.window_frames =
      std::max(options.gap_fill.max_spline_gap + 2, static_cast<int>(std::lround(0.25 * rate_hz)));
  return options;
}

}  // namespace

OfflineReconstruction::OfflineReconstruction(const Rig& rig, double rate_hz, OfflineReconstructionOptions options,
                                             RowSink sink)
    : options_(AtRate(std::move(options), rate_hz)),
      reconstructor_(rig, options_.recon),
      tracker_(options_.tracker),
      filler_(options_.gap_fill, std::move(sink)),
      hindsight_(options_.hindsight, [this](uint64_t frame, const std::vector<TrackSample>& row) {
        filler_.Add(frame, row);
      }) {}

bool OfflineReconstruction::Add(const FrameSet& set) {
  if (frames_ > 0 && set.frame_number <= last_frame_) return false;
  ++frames_;
  last_frame_ = set.frame_number;
  reconstructor_.Process(set, tracker_.Predict(set.frame_number), &points_);
  tracker_.FollowPointNoise(reconstructor_.point_noise_mm());
  samples_.clear();
  tracker_.Update(set.frame_number, points_, &samples_);
  hindsight_.Add(set.frame_number, samples_);
  return true;
}

int OfflineReconstruction::Finish() {
  samples_.clear();
  tracker_.Finish(&samples_);
  hindsight_.Add(last_frame_, samples_);
  hindsight_.Finish();
  filler_.Finish();
  return options_.hindsight.enabled ? hindsight_.num_columns() : tracker_.NumMarkers();
}

}  // namespace mocap::pipeline

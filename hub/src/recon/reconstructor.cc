// The per-frame reconstruction pipeline.
#include "recon/reconstructor.h"

#include <algorithm>

namespace mocap {

Reconstructor::Reconstructor(const Rig& rig, const ReconstructorOptions& options)
    : rig_(rig),
      options_((options.Check(), options)),
      matcher_(CreateMatcher(options)),
      prediction_matcher_(options.prediction, options.triangulation),
      ghost_filter_(options.ghosts, options.triangulation) {}

void Reconstructor::Process(const FrameSet& frame_set,
                            const std::vector<PointPrediction>& predictions,
                            std::vector<ReconstructedPoint>* points) {
  BuildFrameViews(rig_, frame_set, &views_);
  used_.assign(views_.NumObservations(), 0);
  triangulated_.clear();
  track_ids_.clear();
  index_.Build(rig_, views_);
  if (options_.use_predictions && !predictions.empty()) {
    stats_.coincident_blobs += FindSharedBlobs(rig_, views_, index_, predictions, options_.prediction.coincident_px,
                                               options_.triangulation.min_depth_mm, &shared_);
    prediction_matcher_.Match(rig_, views_, index_, predictions, &used_, &triangulated_, &track_ids_, &shared_);
  }
  size_t from_predictions = triangulated_.size();
  stats_.observations += views_.NumObservations();
  for (int i = 0; i < views_.NumObservations(); ++i) stats_.leftover_observations += used_[i] == 0;
  matcher_->Match(rig_, views_, &used_, &triangulated_);
  // Matchers work on whole cliques; a view a clique missed (an edge just over the threshold)
  // joins its point here, before another point could claim it.
  for (size_t i = from_predictions; i < triangulated_.size(); ++i) {
    const std::vector<int> before = triangulated_[i].observations;
    CompleteViews(rig_, views_, index_, used_, options_.triangulation, &triangulated_[i]);
    const std::vector<int>& after = triangulated_[i].observations;
    for (int o : before) {
      if (std::find(after.begin(), after.end(), o) == after.end()) --used_[o];
    }
    for (int o : after) {
      if (std::find(before.begin(), before.end(), o) == before.end()) ++used_[o];
    }
  }
  stats_.ghosts_rejected += ghost_filter_.Apply(rig_, views_, index_, triangulated_, from_predictions, &used_, &keep_);
  size_t kept = 0, kept_from_predictions = 0;
  for (size_t i = 0; i < triangulated_.size(); ++i) {
    if (!keep_[i]) continue;
    if (i < from_predictions) track_ids_[kept_from_predictions++] = track_ids_[i];
    if (kept != i) triangulated_[kept] = std::move(triangulated_[i]);
    ++kept;
  }
  triangulated_.resize(kept);
  track_ids_.resize(kept_from_predictions);
  from_predictions = kept_from_predictions;

  points->clear();
  points->reserve(triangulated_.size());
  for (size_t i = 0; i < triangulated_.size(); ++i) {
    ReconstructedPoint out;
    out.point_in_world = triangulated_[i].point_in_world;
    out.num_views = static_cast<int>(triangulated_[i].observations.size());
    out.rms_px = triangulated_[i].rms_px;
    out.track_hint = i < from_predictions ? track_ids_[i] : -1;
    points->push_back(out);
    stats_.outlier_views_rejected += static_cast<long long>(triangulated_[i].rejected.size());
  }
  ++stats_.frames;
  stats_.points += static_cast<long long>(triangulated_.size());
  stats_.points_from_predictions += static_cast<long long>(from_predictions);
  if (views_.skipped_unknown_cameras > 0) stats_.unknown_camera_frames += views_.skipped_unknown_cameras;
}

}  // namespace mocap

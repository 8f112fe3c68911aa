// The per-frame reconstruction pipeline.
#include "recon/reconstructor.h"

#include "recon/seed_cameras.h"

#include <algorithm>
#include <chrono>
#include <cmath>

namespace mocap {
namespace {

using Clock = std::chrono::steady_clock;

// Adds the time since *since to *total and restarts *since.
void Lap(Clock::time_point* since, double* total) {
  const Clock::time_point now = Clock::now();
  *total += std::chrono::duration<double, std::micro>(now - *since).count();
  *since = now;
}

}  // namespace

Reconstructor::Reconstructor(const Rig& rig, const ReconstructorOptions& options)
    : rig_(rig),
      configured_((options.Check(), options)),
      mm_per_px_(RigMmPerPx(rig)),
      noise_meter_(options.centroid_noise_px > 0.0 ? options.centroid_noise_px : CalibratedNoisePx(rig)),
      gate_noise_px_(noise_meter_.sigma_px()),
      options_(GatesForNoise(configured_, gate_noise_px_, mm_per_px_)),
      matcher_(CreateMatcher(options_)),
      prediction_matcher_(options_.prediction, options_.triangulation),
      group_resolver_(options_.prediction, options_.triangulation),
      ghost_filter_(options_.ghosts, options_.triangulation),
      seed_mask_(SpreadCameras(rig_, options.seed_cameras)),
      team_(options_.threads) {}

void Reconstructor::FollowNoise(double sigma_px) {
  if (std::abs(sigma_px - gate_noise_px_) <= 0.1 * gate_noise_px_) return;
  const ReconstructorOptions gates = GatesForNoise(configured_, sigma_px, mm_per_px_);
  gate_noise_px_ = sigma_px;
  const auto same = [](const ReconstructorOptions& a, const ReconstructorOptions& b) {
    return a.triangulation.max_reprojection_px == b.triangulation.max_reprojection_px &&
           a.triangulation.max_merged_px == b.triangulation.max_merged_px &&
           a.graph.max_ray_distance_mm == b.graph.max_ray_distance_mm &&
           a.clustering.max_ray_distance_mm == b.clustering.max_ray_distance_mm &&
           a.prediction.min_gate_px == b.prediction.min_gate_px && a.prediction.max_gate_px == b.prediction.max_gate_px;
  };
  // A rig as precise as the configured gates assume keeps them (and its matcher's buffers).
  if (same(gates, options_)) return;
  options_ = gates;
  matcher_ = CreateMatcher(options_);
  prediction_matcher_.SetOptions(options_.prediction, options_.triangulation);
  group_resolver_.SetOptions(options_.prediction, options_.triangulation);
  ghost_filter_.SetTriangulationOptions(options_.triangulation);
}

double Reconstructor::point_noise_mm() const {
  return gate_noise_px_ * mm_per_px_ * std::sqrt(2.0 / std::max(2.0, mean_views_));
}

void Reconstructor::CompleteFrom(size_t first) {
  // Matchers work on whole cliques; a view a clique missed (an edge just over the threshold)
  // joins its point here, before another point could claim it.
  for (size_t i = first; i < triangulated_.size(); ++i) {
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
}

int Reconstructor::ComputeLeftoverRays(int* available) {
  // Every blob a matcher may use this frame is available now: matching only takes blobs (the
  // seed cameras' pass sets the others aside and gives them back).
  int unused = 0;
  *available = 0;
  for (int i = 0; i < views_.NumObservations(); ++i) {
    unused += used_[i] == 0;
    if (IsAvailable(views_.observations[i], used_[i])) {
      ComputeRay(rig_, &views_.observations[i]);
      ++*available;
    }
  }
  return unused;
}

void Reconstructor::MatchLeftovers(int leftover) {
  const int num_cameras = rig_.NumCameras();
  if (!seed_mask_.empty() && leftover > options_.seed_from_blobs_per_camera * num_cameras) {
    // Two more uses make a blob unavailable to every matcher whatever its flags; taken back
    // once the seed cameras' points have their other views.
    for (int c = 0; c < num_cameras; ++c) {
      if (seed_mask_[c]) continue;
      for (int o = views_.camera_begin[c]; o < views_.camera_begin[c + 1]; ++o) used_[o] += 2;
    }
    const size_t first = triangulated_.size();
    matcher_->Match(rig_, views_, &used_, &triangulated_);
    for (int c = 0; c < num_cameras; ++c) {
      if (seed_mask_[c]) continue;
      for (int o = views_.camera_begin[c]; o < views_.camera_begin[c + 1]; ++o) used_[o] -= 2;
    }
    CompleteFrom(first);
  }
  const size_t first = triangulated_.size();
  matcher_->Match(rig_, views_, &used_, &triangulated_);
  CompleteFrom(first);
}

void Reconstructor::Process(const FrameSet& frame_set,
                            const std::vector<PointPrediction>& predictions,
                            std::vector<ReconstructedPoint>* points) {
  Clock::time_point lap = Clock::now();
  LayoutFrameViews(rig_, frame_set, &views_, &frame_of_camera_);
  // Rays are left for the blobs the predictions leave (ComputeLeftoverRays): only matchers read them.
  team_.Run(rig_.NumCameras(),
            [&](int c) { UndistortCamera(rig_, frame_set, frame_of_camera_, c, &views_, /*with_rays=*/false); });
  used_.assign(views_.NumObservations(), 0);
  triangulated_.clear();
  track_ids_.clear();
  Lap(&lap, &stage_times_.views_us);
  index_.Resize(rig_);
  team_.Run(rig_.NumCameras(), [&](int c) { index_.BuildCamera(rig_, views_, c); });
  Lap(&lap, &stage_times_.index_us);
  // Blobs two predictions share are only set aside for precise points (precise_fraction), which
  // a rig as noisy as the last frame's points were cannot make: then the search is skipped.
  const bool predicting = options_.use_predictions && !predictions.empty();
  const bool look_for_shared = predicting && median_rms_px_ < PreciseGatePx(options_.triangulation);
  if (predicting) {
    if (look_for_shared) {
      stats_.coincident_blobs += FindSharedBlobs(rig_, views_, index_, predictions, options_.prediction.coincident_px,
                                                 options_.triangulation.min_depth_mm, &shared_, &team_);
    }
    prediction_matcher_.Match(rig_, views_, index_, predictions, &used_, &triangulated_, &track_ids_,
                              look_for_shared ? &shared_ : nullptr, &team_);
  }
  stats_.predictions_served_again = prediction_matcher_.served_again();
  Lap(&lap, &stage_times_.predictions_us);
  // The points before from_predictions carry track hints; the contested groups' points follow
  // them unhinted, like the matcher's.
  size_t from_predictions = triangulated_.size();
  if (predicting && options_.prediction.resolve_contested_groups) {
    stats_.points_from_contested_groups +=
        group_resolver_.Resolve(rig_, views_, index_, predictions, prediction_matcher_.contested(), &used_,
                                &triangulated_, look_for_shared ? &shared_ : nullptr);
  }
  Lap(&lap, &stage_times_.groups_us);
  stats_.observations += views_.NumObservations();
  int available = 0;
  const int leftover = ComputeLeftoverRays(&available);
  stats_.leftover_observations += leftover;
  // No blob left: nothing for the matcher to find (a dense set whose every marker was served).
  if (available > 0) {
    MatchLeftovers(leftover);
    ++stats_.matcher_runs;
  }
  Lap(&lap, &stage_times_.matcher_us);
  stats_.ghosts_rejected += ghost_filter_.Apply(rig_, views_, index_, triangulated_, from_predictions, &used_, &keep_);
  Lap(&lap, &stage_times_.ghosts_us);
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
  if (!triangulated_.empty()) {
    rms_scratch_.clear();
    for (const TriangulatedPoint& point : triangulated_) rms_scratch_.push_back(point.rms_px);
    std::nth_element(rms_scratch_.begin(), rms_scratch_.begin() + rms_scratch_.size() / 2, rms_scratch_.end());
    median_rms_px_ = rms_scratch_[rms_scratch_.size() / 2];
  }
  if (!triangulated_.empty()) {
    size_t views = 0;
    for (const TriangulatedPoint& point : triangulated_) views += point.observations.size();
    mean_views_ = static_cast<double>(views) / static_cast<double>(triangulated_.size());
  }
  if (configured_.follow_measured_noise && !(configured_.centroid_noise_px > 0.0)) {
    noise_meter_.AddFrame(triangulated_);
    if (noise_meter_.frames_measured() > 0) FollowNoise(noise_meter_.sigma_px());
  }
  ++stats_.frames;
  stats_.points += static_cast<long long>(triangulated_.size());
  stats_.points_from_predictions += static_cast<long long>(from_predictions);
  if (views_.skipped_unknown_cameras > 0) stats_.unknown_camera_frames += views_.skipped_unknown_cameras;
}

}  // namespace mocap

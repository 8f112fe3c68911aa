// Live rigid-body orientations refined from past frames (see body_live_filter.h).
#include "bodies/body_live_filter.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

#include <Eigen/Cholesky>

namespace mocap {
namespace {

// Degrees of freedom before the noise estimate is trusted: five frame-to-frame changes of a
// 4-marker body's residuals (12 each).
constexpr double kMinNoiseDof = 60.0;

}  // namespace

void BodyLiveFilterOptions::Check() const {
  if (past_frames < 0 || past_frames > 100) throw std::invalid_argument("live body filter: past frames must be 0..100");
  if (degree < 1 || degree > 3) throw std::invalid_argument("live body filter: degree must be 1..3");
  if (!(test_z > 0.0 && test_z < 10.0)) throw std::invalid_argument("live body filter: test quantile must be in (0, 10)");
  if (!(agreement_z > 0.0 && agreement_z < 10.0))
    throw std::invalid_argument("live body filter: agreement quantile must be in (0, 10)");
}

BodyLiveFilter::BodyLiveFilter(std::vector<RigidBodyDefinition> bodies, const BodyLiveFilterOptions& options)
    : bodies_(std::move(bodies)), options_(options), states_(bodies_.size()) {
  options_.Check();
  agreement_limit_ = ChiSquareQuantile(3.0, options_.agreement_z);
}

BodyLiveFilterStats BodyLiveFilter::stats(size_t body) const {
  BodyLiveFilterStats s = states_.at(body).stats;
  const State& state = states_[body];
  s.noise_mm = state.change_dof > 0.0 ? std::sqrt(state.change_sq / state.change_dof) : 0.0;
  return s;
}

void BodyLiveFilter::Update(uint64_t frame_number, const std::vector<Eigen::Vector3d>& points,
                            std::vector<BodyPose>* poses) {
  if (poses->size() != bodies_.size()) throw std::invalid_argument("live body filter: one pose per body needed");
  if (started_ && frame_number <= last_frame_)
    for (State& state : states_) state.past.clear();
  started_ = true;
  last_frame_ = frame_number;
  for (size_t b = 0; b < bodies_.size(); ++b) {
    BodyPose& pose = (*poses)[b];
    markers_.in_body.clear();
    markers_.in_world.clear();
    if (pose.tracked) {
      for (size_t i = 0; i < pose.point_of_marker.size() && i < bodies_[b].markers.size(); ++i) {
        const int p = pose.point_of_marker[i];
        if (p < 0 || static_cast<size_t>(p) >= points.size()) continue;
        markers_.in_body.push_back(bodies_[b].markers[i]);
        markers_.in_world.push_back(points[static_cast<size_t>(p)]);
      }
    }
    TrackResidualChanges(b, frame_number, points, pose);
    Refine(b, frame_number, markers_, &pose);
  }
}

void BodyLiveFilter::TrackResidualChanges(size_t body, uint64_t frame_number, const std::vector<Eigen::Vector3d>& points,
                                          const BodyPose& pose) {
  State& state = states_[body];
  const size_t n = bodies_[body].markers.size();
  state.residuals.resize(n);
  state.has_residual.resize(n, 0);
  const bool consecutive = state.residual_frame + 1 == frame_number;
  state.residual_frame = frame_number;
  if (!pose.tracked) {
    std::fill(state.has_residual.begin(), state.has_residual.end(), 0);
    return;
  }
  const Eigen::Matrix3d r = pose.orientation.toRotationMatrix();
  double change = 0.0;
  int both = 0, fitted = 0;
  for (size_t i = 0; i < n; ++i) {
    const int p = i < pose.point_of_marker.size() ? pose.point_of_marker[i] : -1;
    if (p < 0 || static_cast<size_t>(p) >= points.size()) {
      state.has_residual[i] = 0;
      continue;
    }
    const Eigen::Vector3d residual =
        r.transpose() * (points[static_cast<size_t>(p)] - pose.position) - bodies_[body].markers[i];
    ++fitted;
    if (consecutive && state.has_residual[i]) change += (residual - state.residuals[i]).squaredNorm(), ++both;
    state.residuals[i] = residual;
    state.has_residual[i] = 1;
  }
  // Two independent fits of the same N markers: their residuals' difference holds 2 (3N - 6)
  // noise variances.
  if (both == fitted && both >= 3) {
    state.change_sq += change;
    state.change_dof += 2.0 * (3.0 * both - 6.0);
  }
}

void BodyLiveFilter::Refine(size_t body, uint64_t frame_number, const BodyFrameMarkers& markers, BodyPose* pose) {
  State& state = states_[body];
  const uint64_t horizon = static_cast<uint64_t>(options_.past_frames);
  while (!state.past.empty() && frame_number - state.past.front().frame > horizon) state.past.pop_front();
  const BodyFrameFit fit = DescribeFrameFit(*pose, markers);
  if (!fit.usable) return;
  const double variance = state.change_dof > 0.0 ? state.change_sq / state.change_dof : 0.0;
  bool refined = false;
  if (options_.past_frames > 0 && state.change_dof >= kMinNoiseDof && variance > 1e-12 && !state.past.empty()) {
    // This frame at t = 0, the past at t < 0; smaller windows keep the frames within |t| <= k.
    samples_.clear();
    for (const PastFit& p : state.past)
      samples_.push_back({-static_cast<double>(frame_number - p.frame), &p.fit.rotation, &p.fit.information});
    samples_.push_back({0.0, &fit.rotation, &fit.information});
    // Windows from the longest down, each about a sixth shorter than the last.
    for (int k = options_.past_frames; k >= 1; k = std::min(k - 1, (5 * k) / 6)) {
      const RotationCurveFit curve = FitRotationCurve(samples_, fit.rotation, k, options_.degree, variance, options_.test_z);
      if (curve.outcome == RotationCurveFit::kTooFewFrames) break;  // shorter windows hold fewer frames
      if (curve.outcome != RotationCurveFit::kAccepted) continue;
      if (!EndAgreesWithHigherDegree(curve, k, variance)) continue;
      SetRefinedOrientation(bodies_[body], fit, markers, curve.rotation_at_zero, pose);
      ++(k == options_.past_frames ? state.stats.refined : state.stats.shrunk);
      refined = true;
      break;
    }
  }
  state.stats.unchanged += !refined;
  // The history holds the frames' own fits: a refined value is not fed back.
  state.past.push_back({frame_number, fit});
}

bool BodyLiveFilter::EndAgreesWithHigherDegree(const RotationCurveFit& curve, int k, double variance) const {
  const RotationCurveFit higher =
      FitRotationCurve(samples_, *samples_.back().rotation, k, options_.degree + 1, variance, options_.test_z);
  if (higher.outcome == RotationCurveFit::kTooFewFrames || higher.outcome == RotationCurveFit::kSingular) return true;
  // Both fit the same frames, the lower degree nested in the higher: their difference at t = 0
  // has the covariance of the higher's minus the lower's.
  const Eigen::Vector3d d = RotationLog(higher.rotation_at_zero * curve.rotation_at_zero.transpose());
  const Eigen::Matrix3d spread = higher.covariance_at_zero - curve.covariance_at_zero;
  const Eigen::LDLT<Eigen::Matrix3d> solver(spread);
  if (solver.info() != Eigen::Success || !solver.isPositive()) return true;
  return d.dot(solver.solve(d)) <= agreement_limit_;
}

LiveBodyTracker::LiveBodyTracker(std::vector<RigidBodyDefinition> bodies, const BodyTrackerOptions& tracker,
                                 const BodyLiveFilterOptions& filter)
    : tracker_(bodies, tracker), filter_(std::move(bodies), filter) {}

const std::vector<BodyPose>& LiveBodyTracker::Update(uint64_t frame_number, const std::vector<Eigen::Vector3d>& points) {
  poses_ = tracker_.Update(points);
  filter_.Update(frame_number, points, &poses_);
  return poses_;
}

}  // namespace mocap

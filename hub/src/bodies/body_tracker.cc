// Rigid-body identity and pose per frame (see body_tracker.h).
#include "bodies/body_tracker.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>
#include <stdexcept>
#include <tuple>

#include "geometry/rigid_fit.h"

namespace mocap {
namespace {

constexpr size_t kMaxHypotheses = 2000;

Eigen::Matrix3d Exp(const Eigen::Vector3d& rotation_vector) {
  const double angle = rotation_vector.norm();
  if (angle < 1e-12) return Eigen::Matrix3d::Identity();
  return Eigen::AngleAxisd(angle, rotation_vector / angle).toRotationMatrix();
}

Eigen::Vector3d Log(const Eigen::Matrix3d& rotation) {
  const Eigen::AngleAxisd aa(rotation);
  return aa.angle() * aa.axis();
}

// The free points sorted by x, for windows of candidates around a point.
struct FreePoints {
  std::vector<int> index;  // into the frame's points, by increasing x
  std::vector<double> x;
  // [first, last) of the entries whose x is within `reach` of `x0`.
  std::pair<size_t, size_t> Window(double x0, double reach) const {
    const auto lo = std::lower_bound(x.begin(), x.end(), x0 - reach);
    const auto hi = std::upper_bound(x.begin(), x.end(), x0 + reach);
    return {static_cast<size_t>(lo - x.begin()), static_cast<size_t>(hi - x.begin())};
  }
};

}  // namespace

void BodyTrackerOptions::Check() const {
  if (!(distance_tolerance_mm > 0.0) || !(max_marker_error_mm > 0.0) || !(track_gate_mm > 0.0))
    throw std::invalid_argument("body tracking tolerances must be > 0");
  if (min_markers_start < 3 || min_markers_continue < 3) throw std::invalid_argument("a pose needs at least 3 markers");
  if (predict_frames < 0) throw std::invalid_argument("predict frames must be >= 0");
  if (max_points == 0) throw std::invalid_argument("max points must be > 0");
}

BodyTracker::BodyTracker(std::vector<RigidBodyDefinition> bodies, const BodyTrackerOptions& options)
    : bodies_(std::move(bodies)), options_(options), states_(bodies_.size()) {
  options_.Check();
  for (const RigidBodyDefinition& b : bodies_)
    if (b.markers.size() < 3) throw std::invalid_argument("body '" + b.name + "' has fewer than 3 markers");
}

const char* BodyMissText(BodyMiss miss) {
  switch (miss) {
    case BodyMiss::kNone: return "fitted";
    case BodyMiss::kTooFewPoints: return "too few free points in the frame";
    case BodyMiss::kNoShape: return "no three points with the sides of its triangles";
    case BodyMiss::kTooFewMarkers: return "too few of its markers where its triangles placed it";
    case BodyMiss::kCrowded: return "too many points in the frame to search";
  }
  return "unknown";
}

std::vector<BodyPose> BodyTracker::Update(const std::vector<Eigen::Vector3d>& points, std::vector<int>* owner_out) {
  std::vector<int> owner(points.size(), -1);
  std::vector<BodyPose> poses(bodies_.size());
  std::vector<bool> done(bodies_.size(), false);
  std::vector<BodyMiss> miss(bodies_.size(), BodyMiss::kCrowded);
  auto take = [&](size_t b) {
    for (int p : poses[b].point_of_marker)
      if (p >= 0) owner[static_cast<size_t>(p)] = static_cast<int>(b);
    Remember(b, poses[b]);
    done[b] = true;
  };
  // Bodies being tracked choose first, in the order of their last fit's quality is not needed:
  // their gates are small, so they rarely compete.
  for (size_t b = 0; b < bodies_.size(); ++b)
    if (states_[b].known && states_[b].frames_since <= options_.predict_frames && Follow(b, points, owner, &poses[b]))
      take(b);
  if (points.size() <= options_.max_points)
    for (size_t b = 0; b < bodies_.size(); ++b)
      if (!done[b] && Search(b, points, owner, &poses[b], &miss[b])) take(b);
  for (size_t b = 0; b < bodies_.size(); ++b) {
    if (done[b]) continue;
    State& s = states_[b];
    BodyPose& pose = poses[b];
    pose = BodyPose{};
    pose.point_of_marker.assign(bodies_[b].markers.size(), -1);
    pose.miss = miss[b];
    ++s.frames_since;
    if (s.known && s.frames_since <= options_.predict_frames) {
      const double k = s.frames_since;
      const Eigen::Matrix3d r = Exp(s.angular * k) * s.rotation;
      pose.predicted = true;
      pose.orientation = Eigen::Quaterniond(r);
      pose.position = s.translation + s.velocity * k;
      pose.pivot = r * bodies_[b].pivot + pose.position;
    } else {
      s.known = false;
    }
  }
  if (owner_out) *owner_out = std::move(owner);
  return poses;
}

bool BodyTracker::Follow(size_t b, const std::vector<Eigen::Vector3d>& points, const std::vector<int>& owner,
                         BodyPose* pose) {
  const State& s = states_[b];
  const RigidBodyDefinition& body = bodies_[b];
  const double k = s.frames_since + 1;
  const Eigen::Matrix3d r = Exp(s.angular * k) * s.rotation;
  const Eigen::Vector3d t = s.translation + s.velocity * k;
  // Every (marker, point) pair within the gate, nearest first, taken greedily one to one.
  std::vector<std::tuple<double, size_t, size_t>> pairs;
  for (size_t m = 0; m < body.markers.size(); ++m) {
    const Eigen::Vector3d predicted = r * body.markers[m] + t;
    for (size_t p = 0; p < points.size(); ++p) {
      if (owner[p] >= 0) continue;
      const double d = (points[p] - predicted).norm();
      if (d <= options_.track_gate_mm) pairs.emplace_back(d, m, p);
    }
  }
  std::sort(pairs.begin(), pairs.end());
  *pose = BodyPose{};
  pose->point_of_marker.assign(body.markers.size(), -1);
  std::vector<bool> point_used(points.size(), false);
  for (const auto& [d, m, p] : pairs) {
    if (pose->point_of_marker[m] >= 0 || point_used[p]) continue;
    pose->point_of_marker[m] = static_cast<int>(p);
    point_used[p] = true;
  }
  return FitAndPrune(b, points, pose, options_.min_markers_continue);
}

bool BodyTracker::FitAndPrune(size_t b, const std::vector<Eigen::Vector3d>& points, BodyPose* pose, size_t min_markers) {
  const RigidBodyDefinition& body = bodies_[b];
  while (true) {
    std::vector<Eigen::Vector3d> source, target;
    std::vector<size_t> which;
    for (size_t m = 0; m < body.markers.size(); ++m) {
      const int p = pose->point_of_marker[m];
      if (p < 0) continue;
      source.push_back(body.markers[m]);
      target.push_back(points[static_cast<size_t>(p)]);
      which.push_back(m);
    }
    if (source.size() < min_markers) return false;
    SimilarityTransform fit;
    try {
      fit = FitRigid(source, target);
    } catch (const std::invalid_argument&) {
      return false;  // the markers left are collinear
    }
    double worst = -1.0, sum = 0.0;
    size_t worst_at = 0;
    for (size_t i = 0; i < source.size(); ++i) {
      const double e = (fit.Apply(source[i]) - target[i]).norm();
      sum += e;
      if (e > worst) worst = e, worst_at = i;
    }
    if (worst > options_.max_marker_error_mm) {
      pose->point_of_marker[which[worst_at]] = -1;  // an outlier: fit again without it
      continue;
    }
    pose->tracked = true;
    pose->predicted = false;
    pose->orientation = Eigen::Quaterniond(fit.rotation).normalized();
    pose->position = fit.translation;
    pose->pivot = fit.rotation * body.pivot + fit.translation;
    pose->mean_error_mm = sum / static_cast<double>(source.size());
    pose->markers = source.size();
    return true;
  }
}

bool BodyTracker::Search(size_t b, const std::vector<Eigen::Vector3d>& points, const std::vector<int>& owner,
                         BodyPose* pose, BodyMiss* miss) {
  const RigidBodyDefinition& body = bodies_[b];
  const size_t n = body.markers.size();
  const double tol = options_.distance_tolerance_mm;
  FreePoints free;
  for (size_t p = 0; p < points.size(); ++p)
    if (owner[p] < 0) free.index.push_back(static_cast<int>(p));
  const size_t min_start = std::min(options_.min_markers_start, n);
  *miss = BodyMiss::kTooFewPoints;
  if (free.index.size() < min_start) return false;
  *miss = BodyMiss::kNoShape;
  std::sort(free.index.begin(), free.index.end(), [&](int a, int c) { return points[static_cast<size_t>(a)].x() < points[static_cast<size_t>(c)].x(); });
  for (int p : free.index) free.x.push_back(points[static_cast<size_t>(p)].x());

  BodyPose best;
  bool found = false;
  size_t hypotheses = 0;  // bounded: a crowd of loose markers cannot make one frame take long
  auto consider = [&](size_t a, size_t c2, size_t c3, int pa, int pb, int pc) {
    // The three correspondences place the body; every marker then takes the free point nearest
    // to where it lands, if close enough, and the whole set is fitted and pruned.
    SimilarityTransform fit;
    try {
      fit = FitRigid({body.markers[a], body.markers[c2], body.markers[c3]},
                     {points[static_cast<size_t>(pa)], points[static_cast<size_t>(pb)], points[static_cast<size_t>(pc)]});
    } catch (const std::invalid_argument&) {
      return;
    }
    BodyPose candidate;
    candidate.point_of_marker.assign(n, -1);
    std::vector<bool> used(points.size(), false);
    for (size_t m = 0; m < n; ++m) {
      const Eigen::Vector3d at = fit.Apply(body.markers[m]);
      double best_d = 2.0 * options_.max_marker_error_mm;
      int best_p = -1;
      for (auto [lo, hi] = free.Window(at.x(), best_d); lo < hi; ++lo) {
        const int p = free.index[lo];
        const double d = (points[static_cast<size_t>(p)] - at).norm();
        if (d < best_d && !used[static_cast<size_t>(p)]) best_d = d, best_p = p;
      }
      if (best_p >= 0) candidate.point_of_marker[m] = best_p, used[static_cast<size_t>(best_p)] = true;
    }
    if (!FitAndPrune(b, points, &candidate, min_start)) return;
    if (!found || candidate.markers > best.markers ||
        (candidate.markers == best.markers && candidate.mean_error_mm < best.mean_error_mm)) {
      best = candidate;
      found = true;
    }
  };
  // Triangles of the body's markers, the largest first (their sides tell bodies apart best).
  std::vector<std::array<size_t, 3>> triangles;
  for (size_t a = 0; a < n; ++a)
    for (size_t c2 = a + 1; c2 < n; ++c2)
      for (size_t c3 = c2 + 1; c3 < n; ++c3) triangles.push_back({a, c2, c3});
  auto side = [&](size_t i, size_t j) { return (body.markers[i] - body.markers[j]).norm(); };
  std::sort(triangles.begin(), triangles.end(), [&](const auto& u, const auto& v) {
    return side(u[0], u[1]) + side(u[0], u[2]) + side(u[1], u[2]) > side(v[0], v[1]) + side(v[0], v[2]) + side(v[1], v[2]);
  });
  for (const auto& [a, c2, c3] : triangles) {
    const double dab = side(a, c2), dac = side(a, c3), dbc = side(c2, c3);
    for (size_t i = 0; i < free.index.size(); ++i) {
      const Eigen::Vector3d& pi = points[static_cast<size_t>(free.index[i])];
      for (auto [lo, hi] = free.Window(pi.x(), dab + tol); lo < hi; ++lo) {
        if (lo == i) continue;
        const Eigen::Vector3d& pj = points[static_cast<size_t>(free.index[lo])];
        if (std::abs((pi - pj).norm() - dab) > tol) continue;
        for (auto [lo2, hi2] = free.Window(pi.x(), dac + tol); lo2 < hi2; ++lo2) {
          if (lo2 == i || lo2 == lo) continue;
          const Eigen::Vector3d& pk = points[static_cast<size_t>(free.index[lo2])];
          if (std::abs((pi - pk).norm() - dac) > tol || std::abs((pj - pk).norm() - dbc) > tol) continue;
          if (++hypotheses > kMaxHypotheses) break;
          *miss = BodyMiss::kTooFewMarkers;
          consider(a, c2, c3, free.index[i], free.index[lo], free.index[lo2]);
        }
      }
    }
    if (found && best.markers == n) break;  // every marker placed: no other triangle can do better
  }
  if (found) *pose = best;
  return found;
}

void BodyTracker::Remember(size_t b, const BodyPose& pose) {
  State& s = states_[b];
  const Eigen::Matrix3d r = pose.orientation.toRotationMatrix();
  if (s.known) {
    const double dt = s.frames_since + 1;
    s.velocity = (pose.position - s.translation) / dt;
    s.angular = Log(r * s.rotation.transpose()) / dt;
  } else {
    s.velocity.setZero();
    s.angular.setZero();
  }
  s.known = true;
  s.frames_since = 0;
  s.rotation = r;
  s.translation = pose.position;
}

}  // namespace mocap

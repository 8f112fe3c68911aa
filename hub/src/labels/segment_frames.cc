// Segment names from the anchors' frame (see segment_frames.h).
#include "labels/segment_frames.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <Eigen/Geometry>

#include "geometry/rigid_fit.h"
#include "util/assignment.h"

namespace mocap {
namespace {

constexpr double kMinAnchorAngleDeg = 25.0;
constexpr double kTurnAxisDeg = 30.0;
constexpr double kPi = 3.14159265358979323846;

Eigen::Vector3d MeanOf(const MarkerSet& set, const std::vector<int>& markers) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (int m : markers) sum += set.mean_shape[static_cast<size_t>(m)];
  return sum / static_cast<double>(markers.size());
}

bool Placed(const MarkerSet& set, int m) {
  return static_cast<size_t>(m) < set.mean_shape.size() && set.mean_shape[static_cast<size_t>(m)].allFinite();
}

// An orthonormal frame (columns) from two directions that are not parallel.
Eigen::Matrix3d FrameOf(const Eigen::Vector3d& u1, const Eigen::Vector3d& u2) {
  const Eigen::Vector3d e1 = u1.normalized();
  const Eigen::Vector3d e2 = (u2 - u2.dot(e1) * e1).normalized();
  Eigen::Matrix3d frame;
  frame.col(0) = e1, frame.col(1) = e2, frame.col(2) = e1.cross(e2);
  return frame;
}

}  // namespace

std::vector<SegmentAnchors> ChooseSegmentAnchors(const MarkerSet& set) {
  const size_t n = set.NumMarkers();
  // Candidate anchors: every segment and every marker in none, placed in the mean shape.
  std::vector<std::vector<int>> groups;
  for (const std::vector<int>& segment : set.segments) {
    std::vector<int> placed;
    for (int m : segment)
      if (Placed(set, m)) placed.push_back(m);
    groups.push_back(placed);
  }
  for (size_t m = 0; m < n; ++m)
    if (set.SegmentOf(static_cast<int>(m)) < 0 && Placed(set, static_cast<int>(m))) groups.push_back({static_cast<int>(m)});
  std::vector<SegmentAnchors> out;
  for (size_t s = 0; s < set.segments.size(); ++s) {
    const std::vector<int>& members = groups[s];
    if (members.size() < 3 || members.size() != set.segments[s].size()) continue;
    const Eigen::Vector3d centre = MeanOf(set, members);
    std::vector<std::pair<double, size_t>> scored;
    std::vector<double> steadiness(groups.size(), 0.0);
    for (size_t g = 0; g < groups.size(); ++g) {
      if (g == s || groups[g].empty()) continue;
      double distance = 0.0, sd = 0.0;
      int count = 0;
      for (int a : members)
        for (int b : groups[g]) {
          const MarkerDistance* d = set.Distance(std::min(a, b), std::max(a, b));
          if (d == nullptr) continue;
          distance += d->mean, sd += d->sd, ++count;
        }
      if (count == 0) continue;
      scored.push_back({(distance + 10.0 * sd) / count, g});
      steadiness[g] = sd / count;
    }
    std::sort(scored.begin(), scored.end());
    // Of the two best, the steadier leads: its direction sets the frame's first axis.
    if (scored.size() >= 2 && steadiness[scored[1].second] < steadiness[scored[0].second]) std::swap(scored[0], scored[1]);
    if (scored.empty()) continue;
    SegmentAnchors anchors;
    anchors.segment = static_cast<int>(s);
    anchors.anchor[0] = groups[scored[0].second];
    const Eigen::Vector3d u1 = MeanOf(set, anchors.anchor[0]) - centre;
    if (u1.norm() < 1e-6) continue;
    for (size_t k = 1; k < scored.size() && anchors.anchor[1].empty(); ++k) {
      const Eigen::Vector3d u2 = MeanOf(set, groups[scored[k].second]) - centre;
      if (u2.norm() < 1e-6) continue;
      const double angle = std::acos(std::clamp(u1.normalized().dot(u2.normalized()), -1.0, 1.0)) * 180.0 / kPi;
      if (angle >= kMinAnchorAngleDeg && angle <= 180.0 - kMinAnchorAngleDeg) anchors.anchor[1] = groups[scored[k].second];
    }
    if (anchors.anchor[1].empty()) continue;
    anchors.limb_axis = u1.normalized();
    double low = 1e300, high = -1e300, across = 0.0;
    for (int m : members) {
      const Eigen::Vector3d offset = set.mean_shape[static_cast<size_t>(m)] - centre;
      const double along = offset.dot(anchors.limb_axis);
      low = std::min(low, along), high = std::max(high, along);
      across = std::max(across, (offset - along * anchors.limb_axis).norm());
    }
    anchors.along_limb = 2.0 * across < 0.5 * (high - low);
    out.push_back(anchors);
  }
  return out;
}

bool IsTurnAboutLimb(const MarkerSet& set, const SegmentAnchors& anchors, const std::vector<std::pair<int, int>>& relabel) {
  if (!anchors.along_limb) return false;
  const std::vector<int>& members = set.segments[static_cast<size_t>(anchors.segment)];
  // The segment's mean shape against itself with the names moved: the turn that takes one onto
  // the other, and its axis.
  std::vector<Eigen::Vector3d> source, target;
  for (int m : members) {
    int to = m;
    for (const auto& [from, into] : relabel)
      if (from == m) to = into;
    source.push_back(set.mean_shape[static_cast<size_t>(m)]);
    target.push_back(set.mean_shape[static_cast<size_t>(to)]);
  }
  Eigen::Matrix3d rotation;
  try {
    rotation = FitRigid(source, target).rotation;
  } catch (const std::invalid_argument&) {
    return true;  // a degenerate segment: nothing is decided
  }
  const Eigen::AngleAxisd turn(rotation);
  if (std::abs(turn.angle()) < 1e-6) return false;
  return std::abs(turn.axis().dot(anchors.limb_axis)) >= std::cos(kTurnAxisDeg * kPi / 180.0);
}

void VoteInSegmentFrames(const MarkerSet& set, const std::vector<SegmentAnchors>& anchors,
                         const std::vector<Eigen::Vector3d>& points, const std::vector<int>& labels,
                         std::vector<int>* votes) {
  votes->assign(points.size(), -1);
  std::vector<int> point_of(set.NumMarkers(), -1);
  for (size_t p = 0; p < points.size(); ++p)
    if (labels[p] >= 0 && static_cast<size_t>(labels[p]) < point_of.size()) point_of[static_cast<size_t>(labels[p])] = static_cast<int>(p);
  auto centroid_now = [&](const std::vector<int>& markers, Eigen::Vector3d* at) {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (int m : markers) {
      const int p = point_of[static_cast<size_t>(m)];
      if (p < 0) return false;
      sum += points[static_cast<size_t>(p)];
    }
    *at = sum / static_cast<double>(markers.size());
    return true;
  };
  for (const SegmentAnchors& a : anchors) {
    const std::vector<int>& members = set.segments[static_cast<size_t>(a.segment)];
    Eigen::Vector3d centre, first, second;
    if (!centroid_now(members, &centre) || !centroid_now(a.anchor[0], &first) || !centroid_now(a.anchor[1], &second))
      continue;
    const Eigen::Vector3d mean_centre = MeanOf(set, members);
    const Eigen::Vector3d u1 = first - centre, u2 = second - centre;
    const Eigen::Vector3d v1 = MeanOf(set, a.anchor[0]) - mean_centre, v2 = MeanOf(set, a.anchor[1]) - mean_centre;
    if (u1.norm() < 1e-6 || (u2 - u2.dot(u1.normalized()) * u1.normalized()).norm() < 1e-6) continue;
    const Eigen::Matrix3d turn = FrameOf(u1, u2) * FrameOf(v1, v2).transpose();
    // The segment's size on this subject (its points' spread about their centre): the scale.
    double spread_now = 0.0, spread_mean = 0.0;
    for (int m : members) {
      spread_now += (points[static_cast<size_t>(point_of[static_cast<size_t>(m)])] - centre).squaredNorm();
      spread_mean += (set.mean_shape[static_cast<size_t>(m)] - mean_centre).squaredNorm();
    }
    if (!(spread_mean > 0.0)) continue;
    const double scale = std::clamp(std::sqrt(spread_now / spread_mean), 0.5, 2.0);
    Eigen::MatrixXd cost(members.size(), members.size());
    for (size_t i = 0; i < members.size(); ++i) {
      const Eigen::Vector3d& at = points[static_cast<size_t>(point_of[static_cast<size_t>(members[i])])];
      for (size_t k = 0; k < members.size(); ++k)
        cost(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(k)) =
            (centre + scale * (turn * (set.mean_shape[static_cast<size_t>(members[k])] - mean_centre)) - at).squaredNorm();
    }
    const std::vector<int> match = SolveAssignment(cost, 1e18);
    for (size_t i = 0; i < members.size(); ++i)
      if (match[i] >= 0)
        (*votes)[static_cast<size_t>(point_of[static_cast<size_t>(members[i])])] = members[static_cast<size_t>(match[i])];
  }
}

}  // namespace mocap

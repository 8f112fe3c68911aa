// Frame-by-frame labelling (see marker_labeller.h).
#include "labels/marker_labeller.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <Eigen/Geometry>

#include "geometry/rigid_fit.h"
#include "labels/marker_set_learning.h"
#include "util/assignment.h"

namespace mocap {
namespace {

constexpr double kPi = 3.14159265358979323846;

bool Finite(const Eigen::Vector3d& p) { return p.allFinite(); }

}  // namespace

void LabellerOptions::Check() const {
  if (up_axis < -1 || up_axis > 2) throw std::invalid_argument("up axis must be 0, 1, 2 or -1");
  if (!(shape_gate_mm > 0.0) || !(local_gate_mm > 0.0) || !(distance_tolerance_mm > 0.0))
    throw std::invalid_argument("labelling gates and tolerances must be > 0");
  if (!(template_tolerance >= 0.0 && template_tolerance < 10.0)) throw std::invalid_argument("template tolerance must be in [0, 10)");
  if (min_votes < 1 || !(min_vote_share > 0.0 && min_vote_share <= 1.0))
    throw std::invalid_argument("votes: at least 1, share in (0, 1]");
  if (learn_frames < 2) throw std::invalid_argument("learn frames must be >= 2");
  if (search_headings < 1 || search_headings > 360) throw std::invalid_argument("search headings must be 1-360");
}

MarkerLabeller::MarkerLabeller(MarkerSet set, const LabellerOptions& options) : set_(std::move(set)), options_(options) {
  options_.Check();
  set_.Index();
  const size_t n = set_.NumMarkers();
  for (size_t m = 0; m < n; ++m)
    if (m < set_.mean_shape.size() && Finite(set_.mean_shape[m])) shape_markers_.push_back(static_cast<int>(m));
  if (shape_markers_.size() < 3) throw std::invalid_argument("the marker set places fewer than 3 markers in its mean shape");
  if (options_.up_axis >= 0) {
    to_canonical_ = UpToZ(options_.up_axis);
    up_known_ = true;
  }
  owner_.assign(n, -1);
  learned_.resize(n * n);
  snapshot_.resize(n);
  has_snapshot_.assign(n, 0);
}

bool MarkerLabeller::DistanceBreaks(int a, int b, double distance) const {
  const size_t n = set_.NumMarkers();
  const PairLearned& l = learned_[static_cast<size_t>(std::min(a, b)) * n + static_cast<size_t>(std::max(a, b))];
  if (l.n >= options_.learn_frames) {
    const double mean = l.sum / l.n;
    const double sd = std::sqrt(std::max(0.0, l.sum_squares / l.n - mean * mean));
    return std::abs(distance - mean) > std::max(options_.distance_tolerance_mm, 5.0 * sd);
  }
  const MarkerDistance* d = set_.Distance(a, b);
  if (d == nullptr) return false;
  const double widen = options_.template_tolerance;
  return distance < d->min * (1.0 - widen) - options_.distance_tolerance_mm ||
         distance > d->max * (1.0 + widen) + options_.distance_tolerance_mm;
}

// Whether `label` at `at` agrees with the labelled points of its segment (self: the point's own
// index, skipped).
bool MarkerLabeller::Consistent(int label, const Eigen::Vector3d& at, const std::vector<Eigen::Vector3d>& points,
                                int self) const {
  const int segment = set_.SegmentOf(label);
  if (segment < 0) return true;
  int checks = 0, breaks = 0;
  for (int b : set_.segments[static_cast<size_t>(segment)]) {
    const int p = point_of_label_[static_cast<size_t>(b)];
    if (b == label || p < 0 || p == self) continue;
    ++checks;
    breaks += DistanceBreaks(label, b, (points[static_cast<size_t>(p)] - at).norm());
  }
  return checks == 0 || 2 * breaks <= checks;
}

void MarkerLabeller::SwapGuard(const std::vector<Eigen::Vector3d>& points, const std::vector<int64_t>& tracks) {
  // Count each labelled point's broken segment distances; take the name from the worst offender
  // first and recount, so that one swapped point does not cost its honest partners their names.
  while (true) {
    int worst = -1, worst_breaks = 0;
    long long worst_since = -1;
    for (size_t p = 0; p < points.size(); ++p) {
      const int a = labels_[p];
      if (a < 0) continue;
      const int segment = set_.SegmentOf(a);
      if (segment < 0) continue;
      int checks = 0, breaks = 0;
      for (int b : set_.segments[static_cast<size_t>(segment)]) {
        const int q = point_of_label_[static_cast<size_t>(b)];
        if (b == a || q < 0) continue;
        ++checks;
        breaks += DistanceBreaks(a, b, (points[p] - points[static_cast<size_t>(q)]).norm());
      }
      Eigen::Vector3d placed;
      if (checks >= 2 && PlaceByPartners(a, points, &placed)) {
        ++checks;
        breaks += (placed - points[p]).norm() > options_.local_gate_mm;
      }
      if (breaks == 0 || 2 * breaks < checks) continue;
      const auto it = tracks[p] >= 0 ? tracks_.find(tracks[p]) : tracks_.end();
      const long long since = it == tracks_.end() ? frame_counter_ : it->second.labelled_since;
      // Most broken first; among equals the name given last (the newer claim is the doubtful one).
      if (breaks > worst_breaks || (breaks == worst_breaks && since > worst_since))
        worst = static_cast<int>(p), worst_breaks = breaks, worst_since = since;
    }
    if (worst < 0) return;
    const int a = labels_[static_cast<size_t>(worst)];
    labels_[static_cast<size_t>(worst)] = -1;
    point_of_label_[static_cast<size_t>(a)] = -1;
    const int64_t track = tracks[static_cast<size_t>(worst)];
    if (track >= 0) {
      TrackState& state = tracks_[track];
      state.label = -1;
      state.votes.clear();
      state.total_votes = 0;
      owner_[static_cast<size_t>(a)] = -1;
      revoked_.push_back(track);
    }
    ++stats_.revocations;
  }
}

bool MarkerLabeller::PlaceByPartners(int label, const std::vector<Eigen::Vector3d>& points, Eigen::Vector3d* at) const {
  if (!has_snapshot_[static_cast<size_t>(label)]) return false;
  const int segment = set_.SegmentOf(label);
  if (segment < 0) return false;
  const std::vector<int>& members = set_.segments[static_cast<size_t>(segment)];
  const std::vector<Eigen::Vector3d>& snap = snapshot_[static_cast<size_t>(label)];
  std::vector<Eigen::Vector3d> then, now;
  Eigen::Vector3d self_then = Eigen::Vector3d::Zero();
  for (size_t i = 0; i < members.size(); ++i) {
    const int b = members[i];
    if (b == label) {
      self_then = snap[i];
      continue;
    }
    const int p = point_of_label_[static_cast<size_t>(b)];
    if (p < 0 || !Finite(snap[i])) continue;
    then.push_back(snap[i]);
    now.push_back(points[static_cast<size_t>(p)]);
  }
  if (now.empty()) return false;
  if (now.size() >= 3) {
    try {
      *at = FitRigid(then, now).Apply(self_then);
      return true;
    } catch (const std::invalid_argument&) {
      // collinear partners: fall through to the two-point rule
    }
  }
  if (now.size() >= 2) {
    // The turn that takes the partners' old direction to the new one, about their midpoint.
    const Eigen::Vector3d u = (then[1] - then[0]).normalized(), v = (now[1] - now[0]).normalized();
    const Eigen::Matrix3d r = Eigen::Quaterniond::FromTwoVectors(u, v).toRotationMatrix();
    *at = r * (self_then - 0.5 * (then[0] + then[1])) + 0.5 * (now[0] + now[1]);
    return true;
  }
  *at = self_then + (now[0] - then[0]);
  return true;
}

double MarkerLabeller::Icp(const std::vector<Eigen::Vector3d>& canonical, UprightTransform* fit, int iterations) const {
  const double gate = 2.0 * options_.shape_gate_mm;
  double score = 0.0;
  for (int it = 0; it < iterations; ++it) {
    Eigen::MatrixXd cost(canonical.size(), shape_markers_.size());
    for (size_t p = 0; p < canonical.size(); ++p)
      for (size_t k = 0; k < shape_markers_.size(); ++k)
        cost(p, k) = (fit->Apply(set_.mean_shape[static_cast<size_t>(shape_markers_[k])]) - canonical[p]).norm();
    const std::vector<int> match = SolveAssignment(cost, gate);
    std::vector<double> residuals;
    for (size_t p = 0; p < canonical.size(); ++p)
      if (match[p] >= 0) residuals.push_back(cost(p, match[p]));
    if (residuals.size() < 3) return 1e300;
    // The best placed 60 % set the fit: swinging limbs do not turn the body.
    std::vector<double> sorted = residuals;
    const size_t keep_count = std::max<size_t>(3, (residuals.size() * 6) / 10);
    std::nth_element(sorted.begin(), sorted.begin() + (keep_count - 1), sorted.end());
    const double keep = sorted[keep_count - 1];
    // The score is that of the best placed 60 % too (the trunk's), plus the gate for every point
    // left unmatched: a body turned the wrong way round matches its swinging limbs as well.
    score = 0.0;
    for (size_t i = 0; i < keep_count; ++i) score += sorted[i] * sorted[i];
    score = score / static_cast<double>(keep_count) +
            gate * gate * static_cast<double>(canonical.size() - residuals.size()) / canonical.size();
    std::vector<Eigen::Vector3d> source, target;
    for (size_t p = 0; p < canonical.size(); ++p)
      if (match[p] >= 0 && cost(p, match[p]) <= keep) {
        source.push_back(set_.mean_shape[static_cast<size_t>(shape_markers_[static_cast<size_t>(match[p])])]);
        target.push_back(canonical[p]);
      }
    if (source.size() < 3) return 1e300;
    *fit = FitUpright(source, target, true);
  }
  return score;
}

bool MarkerLabeller::AlignShape(const std::vector<Eigen::Vector3d>& canonical) {
  // Enough labelled points: the shape goes where they are.
  std::vector<Eigen::Vector3d> source, target;
  for (size_t p = 0; p < canonical.size(); ++p) {
    const int a = labels_[p];
    if (a >= 0 && Finite(set_.mean_shape[static_cast<size_t>(a)]))
      source.push_back(set_.mean_shape[static_cast<size_t>(a)]), target.push_back(canonical[p]);
  }
  if (source.size() >= 4) {
    shape_fit_ = FitUpright(source, target, true);
    if (source.size() >= 6) {  // again on the best placed 60 %: limbs swing
      std::vector<std::pair<double, size_t>> residual;
      for (size_t i = 0; i < source.size(); ++i) residual.push_back({(shape_fit_.Apply(source[i]) - target[i]).norm(), i});
      std::sort(residual.begin(), residual.end());
      std::vector<Eigen::Vector3d> core_source, core_target;
      for (size_t i = 0; i < (residual.size() * 6) / 10; ++i)
        core_source.push_back(source[residual[i].second]), core_target.push_back(target[residual[i].second]);
      shape_fit_ = FitUpright(core_source, core_target, true);
    }
    shape_valid_ = true;
    return true;
  }
  if (canonical.size() < 3) return false;
  // Else continue from the last frame's placement while it still fits, or search.
  const double good = 0.25 * options_.shape_gate_mm * options_.shape_gate_mm;
  if (shape_valid_) {
    UprightTransform fit = shape_fit_;
    if (Icp(canonical, &fit, 3) < good) {
      shape_fit_ = fit;
      return true;
    }
  }
  ++stats_.searches;
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero(), shape_centroid = Eigen::Vector3d::Zero();
  double best = 1e300;
  UprightTransform best_fit;
  Eigen::Matrix3d best_axes = to_canonical_;
  const int axes = up_known_ ? 1 : 6;
  for (int axis = 0; axis < axes; ++axis) {
    Eigen::Matrix3d to = to_canonical_;
    if (!up_known_) {
      to = UpToZ(axis % 3);
      if (axis >= 3) to = Eigen::Vector3d(1.0, -1.0, -1.0).asDiagonal() * to;  // upside down: turned about x
    }
    std::vector<Eigen::Vector3d> turned(canonical.size());
    centroid.setZero();
    for (size_t p = 0; p < canonical.size(); ++p) {
      turned[p] = to * to_canonical_.transpose() * canonical[p];
      centroid += turned[p];
    }
    centroid /= static_cast<double>(turned.size());
    shape_centroid.setZero();
    for (int m : shape_markers_) shape_centroid += set_.mean_shape[static_cast<size_t>(m)];
    shape_centroid /= static_cast<double>(shape_markers_.size());
    for (int h = 0; h < options_.search_headings; ++h) {
      UprightTransform fit;
      fit.yaw = 2.0 * kPi * h / options_.search_headings;
      fit.translation = centroid - fit.Apply(shape_centroid);
      const double score = Icp(turned, &fit, 8);
      if (score < best) best = score, best_fit = fit, best_axes = to;
    }
  }
  if (best >= 1e299) return false;
  if (!up_known_) {
    to_canonical_ = best_axes;
    up_known_ = true;  // found once; kept (a person does not turn over)
  }
  shape_fit_ = best_fit;
  shape_valid_ = true;
  return true;
}

void MarkerLabeller::Learn(const std::vector<Eigen::Vector3d>& points) {
  const size_t n = set_.NumMarkers();
  for (const std::vector<int>& segment : set_.segments) {
    for (size_t i = 0; i < segment.size(); ++i) {
      const int a = segment[i];
      const int p = point_of_label_[static_cast<size_t>(a)];
      if (p < 0) continue;
      for (size_t j = i + 1; j < segment.size(); ++j) {
        const int q = point_of_label_[static_cast<size_t>(segment[j])];
        if (q < 0) continue;
        const double d = (points[static_cast<size_t>(p)] - points[static_cast<size_t>(q)]).norm();
        PairLearned& l = learned_[static_cast<size_t>(std::min(a, segment[j])) * n + static_cast<size_t>(std::max(a, segment[j]))];
        // A long capture keeps adapting: the statistics are a window of about 1000 frames.
        if (l.n >= 1000) l.sum *= 0.999, l.sum_squares *= 0.999, l.n = 999;
        l.sum += d, l.sum_squares += d * d, ++l.n;
      }
      // The snapshot: this label and the partners labelled with it now.
      std::vector<Eigen::Vector3d>& snap = snapshot_[static_cast<size_t>(a)];
      snap.assign(segment.size(), Eigen::Vector3d::Constant(std::nan("")));
      int partners = 0;
      for (size_t j = 0; j < segment.size(); ++j) {
        const int q = point_of_label_[static_cast<size_t>(segment[j])];
        if (q < 0) continue;
        snap[j] = points[static_cast<size_t>(q)];
        partners += segment[j] != a;
      }
      has_snapshot_[static_cast<size_t>(a)] = partners > 0;
    }
  }
}

void MarkerLabeller::Commit(int64_t track, int label) {
  const int64_t old = owner_[static_cast<size_t>(label)];
  if (old >= 0 && old != track) {
    auto it = tracks_.find(old);
    if (it != tracks_.end()) it->second.label = -1;
  }
  TrackState& state = tracks_[track];
  if (state.label >= 0 && state.label != label) owner_[static_cast<size_t>(state.label)] = -1;
  state.label = label;
  state.labelled_since = frame_counter_;
  owner_[static_cast<size_t>(label)] = track;
  ++stats_.commits;
}

void MarkerLabeller::Propose(const std::vector<Eigen::Vector3d>& points, const std::vector<Eigen::Vector3d>& canonical,
                             const std::vector<int64_t>& tracks) {
  const size_t n = set_.NumMarkers();
  // Every point (labelled or not) against every marker placed by the mean shape, each segment
  // shifted to where its points are (a leg swings as a whole): the votes. Squared distances, so
  // that a segment's common shift does not change which of its markers is which.
  std::vector<Eigen::Vector3d> shape_placed(n, Eigen::Vector3d::Constant(std::nan("")));
  if (shape_valid_) {
    std::vector<Eigen::Vector3d> base(shape_markers_.size()), shift(set_.segments.size(), Eigen::Vector3d::Zero());
    for (size_t k = 0; k < shape_markers_.size(); ++k)
      base[k] = shape_fit_.Apply(set_.mean_shape[static_cast<size_t>(shape_markers_[k])]);
    std::vector<int> match;
    for (int round = 0; round < 3; ++round) {
      const double gate = (round == 0 ? 2.0 : 1.0) * options_.shape_gate_mm;
      Eigen::MatrixXd cost(points.size(), shape_markers_.size());
      for (size_t k = 0; k < shape_markers_.size(); ++k) {
        const int segment = set_.SegmentOf(shape_markers_[k]);
        const Eigen::Vector3d at = base[k] + (segment >= 0 ? shift[static_cast<size_t>(segment)] : Eigen::Vector3d::Zero());
        for (size_t p = 0; p < points.size(); ++p) cost(p, k) = (at - canonical[p]).squaredNorm();
      }
      match = SolveAssignment(cost, gate * gate);
      std::vector<Eigen::Vector3d> sum(set_.segments.size(), Eigen::Vector3d::Zero());
      std::vector<int> count(set_.segments.size(), 0);
      for (size_t p = 0; p < points.size(); ++p) {
        if (match[p] < 0) continue;
        const int segment = set_.SegmentOf(shape_markers_[static_cast<size_t>(match[p])]);
        if (segment < 0) continue;
        sum[static_cast<size_t>(segment)] += canonical[p] - base[static_cast<size_t>(match[p])];
        ++count[static_cast<size_t>(segment)];
      }
      for (size_t g = 0; g < shift.size(); ++g)
        shift[g] = count[g] >= 2 ? Eigen::Vector3d(sum[g] / count[g]) : Eigen::Vector3d::Zero();
    }
    for (size_t k = 0; k < shape_markers_.size(); ++k) {
      const int segment = set_.SegmentOf(shape_markers_[k]);
      shape_placed[static_cast<size_t>(shape_markers_[k])] =
          to_canonical_.transpose() *
          (base[k] + (segment >= 0 ? shift[static_cast<size_t>(segment)] : Eigen::Vector3d::Zero()));
    }
    for (size_t p = 0; p < points.size(); ++p) {
      if (match[p] < 0) continue;
      proposals_[p] = shape_markers_[static_cast<size_t>(match[p])];
      if (tracks[p] >= 0) {
        TrackState& state = tracks_[tracks[p]];
        ++state.votes[proposals_[p]];
        ++state.total_votes;
      }
    }
  }
  // Unlabelled points against the markers missing from this frame.
  std::vector<int> free_points, missing;
  for (size_t p = 0; p < points.size(); ++p)
    if (labels_[p] < 0) free_points.push_back(static_cast<int>(p));
  for (size_t a = 0; a < n; ++a)
    if (point_of_label_[a] < 0) missing.push_back(static_cast<int>(a));
  if (free_points.empty() || missing.empty()) return;
  std::vector<Eigen::Vector3d> placed(missing.size());
  std::vector<char> local(missing.size(), 0), known(missing.size(), 0);
  for (size_t k = 0; k < missing.size(); ++k) {
    const int a = missing[k];
    if (PlaceByPartners(a, points, &placed[k])) {
      local[k] = known[k] = 1;
    } else if (Finite(shape_placed[static_cast<size_t>(a)])) {
      placed[k] = shape_placed[static_cast<size_t>(a)];
      known[k] = 1;
    }
  }
  // Cost in gates: a marker placed by its partners is trusted within local_gate, one placed by the
  // mean shape within shape_gate.
  Eigen::MatrixXd cost(free_points.size(), missing.size());
  for (size_t i = 0; i < free_points.size(); ++i)
    for (size_t k = 0; k < missing.size(); ++k) {
      if (!known[k]) {
        cost(i, k) = 1e9;
        continue;
      }
      const double gate = local[k] ? options_.local_gate_mm : options_.shape_gate_mm;
      cost(i, k) = (points[static_cast<size_t>(free_points[i])] - placed[k]).norm() / gate;
    }
  const std::vector<int> match = SolveAssignment(cost, 1.0);
  std::vector<std::pair<int, int>> accepted;  // (point, label)
  for (size_t i = 0; i < free_points.size(); ++i) {
    if (match[i] < 0) continue;
    const int p = free_points[i], a = missing[static_cast<size_t>(match[i])];
    if (!Consistent(a, points[static_cast<size_t>(p)], points, p)) continue;
    const int64_t track = tracks[static_cast<size_t>(p)];
    if (local[static_cast<size_t>(match[i])]) {
      accepted.push_back({p, a});
      if (track >= 0) Commit(track, a);
      continue;
    }
    if (track < 0) continue;  // no guessing from the mean shape for a point without a track
    const TrackState& state = tracks_[track];
    const auto it = state.votes.find(a);
    const int votes = it == state.votes.end() ? 0 : it->second;
    if (votes >= options_.min_votes && votes >= options_.min_vote_share * state.total_votes) {
      accepted.push_back({p, a});
      Commit(track, a);
    }
  }
  for (const auto& [p, a] : accepted) {
    labels_[static_cast<size_t>(p)] = a;
    point_of_label_[static_cast<size_t>(a)] = p;
  }
}

const std::vector<int>& MarkerLabeller::Update(const std::vector<Eigen::Vector3d>& points,
                                               const std::vector<int64_t>& tracks) {
  if (tracks.size() != points.size()) throw std::invalid_argument("labeller: one track per point");
  ++frame_counter_;
  const size_t n = set_.NumMarkers();
  labels_.assign(points.size(), -1);
  proposals_.assign(points.size(), -1);
  revoked_.clear();
  point_of_label_.assign(n, -1);
  // 1. Names of labelled tracks (a track seen twice in a frame keeps its name on the first).
  for (size_t p = 0; p < points.size(); ++p) {
    if (tracks[p] < 0 || !Finite(points[p])) continue;
    const auto it = tracks_.find(tracks[p]);
    if (it == tracks_.end() || it->second.label < 0) continue;
    const int a = it->second.label;
    if (point_of_label_[static_cast<size_t>(a)] >= 0) continue;
    labels_[p] = a;
    point_of_label_[static_cast<size_t>(a)] = static_cast<int>(p);
  }
  // 2. Swap guard.
  SwapGuard(points, tracks);
  // 3. The mean shape, in the z-up frame.
  std::vector<Eigen::Vector3d> canonical;
  std::vector<int> finite;
  for (size_t p = 0; p < points.size(); ++p)
    if (Finite(points[p])) finite.push_back(static_cast<int>(p));
  for (int p : finite) canonical.push_back(to_canonical_ * points[static_cast<size_t>(p)]);
  {
    // AlignShape reads labels_ by position in `canonical`: give it the finite points' labels.
    const std::vector<int> saved = labels_;
    std::vector<int> compact;
    for (int p : finite) compact.push_back(saved[static_cast<size_t>(p)]);
    labels_ = compact;
    AlignShape(canonical);  // fixes to_canonical_ when the up axis was not known
    labels_ = saved;
  }
  std::vector<Eigen::Vector3d> all_canonical(points.size());
  for (size_t p = 0; p < points.size(); ++p)
    all_canonical[p] = Finite(points[p]) ? Eigen::Vector3d(to_canonical_ * points[p]) : Eigen::Vector3d::Constant(1e12);
  // 4. Proposals and new names, then what this frame teaches about the subject.
  Propose(points, all_canonical, tracks);
  Learn(points);
  for (int a : labels_) stats_.named_points += a >= 0;
  return labels_;
}

}  // namespace mocap

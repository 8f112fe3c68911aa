// Fitting the marker set to one frame (see set_fit.h).
#include "labels/set_fit.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "geometry/rigid_fit.h"
#include "labels/shape_fit.h"
#include "util/assignment.h"

namespace mocap {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kCoreShare = 0.6;  // the best placed share of the points that sets the body's fit
constexpr int kIcpRounds = 8;

// Placed markers (per shape marker) against points: distances, one-to-one match within `gate`.
std::vector<int> Match(const std::vector<Eigen::Vector3d>& placed, const std::vector<Eigen::Vector3d>& points,
                       double gate, Eigen::MatrixXd* cost) {
  cost->resize(static_cast<Eigen::Index>(points.size()), static_cast<Eigen::Index>(placed.size()));
  for (size_t p = 0; p < points.size(); ++p)
    for (size_t k = 0; k < placed.size(); ++k) (*cost)(p, k) = (placed[k] - points[p]).norm();
  return SolveAssignment(*cost, gate);
}

class FrameFitter {
 public:
  FrameFitter(const MarkerSet& set, const std::vector<Eigen::Vector3d>& points, const SetFitOptions& options)
      : set_(set), points_(points), options_(options) {
    for (size_t m = 0; m < set.NumMarkers(); ++m)
      if (m < set.mean_shape.size() && set.mean_shape[m].allFinite()) shape_.push_back(static_cast<int>(m));
    if (shape_.size() < 3) throw std::invalid_argument("the marker set places fewer than 3 markers in its mean shape");
  }

  SetFit Fit(const std::vector<int>* known) {
    SetFit out;
    out.labels.assign(points_.size(), -1);
    if (points_.size() < 3) return out;
    known_ = known;
    if (!(known != nullptr && PlaceOnKnown(*known)) && !PlaceBody()) return out;
    out.scale = body_.scale;
    out.score = score_;
    FitSegments();
    Name(known, &out.labels);
    if (known != nullptr)
      for (size_t p = 0; p < points_.size(); ++p)
        if ((*known)[p] >= 0) out.labels[p] = (*known)[p];
    return out;
  }

 private:
  // ICP of the upright similarity from one starting heading; returns the core score.
  double Icp(UprightTransform* fit) const {
    double score = 1e300;
    std::vector<Eigen::Vector3d> placed(shape_.size());
    Eigen::MatrixXd cost;
    for (int round = 0; round < kIcpRounds; ++round) {
      for (size_t k = 0; k < shape_.size(); ++k) placed[k] = fit->Apply(set_.mean_shape[static_cast<size_t>(shape_[k])]);
      const std::vector<int> match = Match(placed, points_, options_.search_gate_mm, &cost);
      std::vector<std::pair<double, size_t>> residuals;
      for (size_t p = 0; p < points_.size(); ++p)
        if (match[p] >= 0) residuals.push_back({cost(p, match[p]), p});
      if (residuals.size() < 3) return 1e300;
      std::sort(residuals.begin(), residuals.end());
      const size_t keep = std::max<size_t>(3, static_cast<size_t>(kCoreShare * residuals.size()));
      score = 0.0;
      std::vector<Eigen::Vector3d> source, target;
      for (size_t i = 0; i < keep; ++i) {
        score += residuals[i].first * residuals[i].first;
        const size_t p = residuals[i].second;
        source.push_back(set_.mean_shape[static_cast<size_t>(shape_[static_cast<size_t>(match[p])])]);
        target.push_back(points_[p]);
      }
      // Points left unmatched count as the gate: a body turned the wrong way matches fewer.
      const double gate = options_.search_gate_mm;
      score = score / static_cast<double>(keep) +
              gate * gate * static_cast<double>(points_.size() - residuals.size()) / static_cast<double>(points_.size());
      *fit = FitUpright(source, target, true);
    }
    return score;
  }

  // The body placed on the names already given (the best placed 60 % of them: limbs swing).
  bool PlaceOnKnown(const std::vector<int>& known) {
    std::vector<Eigen::Vector3d> source, target;
    for (size_t p = 0; p < points_.size(); ++p) {
      const int m = known[p];
      if (m >= 0 && static_cast<size_t>(m) < set_.mean_shape.size() && set_.mean_shape[static_cast<size_t>(m)].allFinite())
        source.push_back(set_.mean_shape[static_cast<size_t>(m)]), target.push_back(points_[p]);
    }
    if (source.size() < 4) return false;
    UprightTransform fit = FitUpright(source, target, true);
    std::vector<std::pair<double, size_t>> residuals;
    for (size_t i = 0; i < source.size(); ++i) residuals.push_back({(fit.Apply(source[i]) - target[i]).norm(), i});
    std::sort(residuals.begin(), residuals.end());
    const size_t keep = std::max<size_t>(3, static_cast<size_t>(kCoreShare * residuals.size()));
    std::vector<Eigen::Vector3d> core_source, core_target;
    score_ = 0.0;
    for (size_t i = 0; i < keep; ++i) {
      core_source.push_back(source[residuals[i].second]), core_target.push_back(target[residuals[i].second]);
      score_ += residuals[i].first * residuals[i].first / static_cast<double>(keep);
    }
    body_ = FitUpright(core_source, core_target, true);
    placed_.resize(shape_.size());
    for (size_t k = 0; k < shape_.size(); ++k) placed_[k] = body_.Apply(set_.mean_shape[static_cast<size_t>(shape_[k])]);
    return true;
  }

  bool PlaceBody() {
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero(), shape_centroid = Eigen::Vector3d::Zero();
    for (const Eigen::Vector3d& p : points_) centroid += p;
    centroid /= static_cast<double>(points_.size());
    for (int m : shape_) shape_centroid += set_.mean_shape[static_cast<size_t>(m)];
    shape_centroid /= static_cast<double>(shape_.size());
    score_ = 1e300;
    for (int h = 0; h < options_.headings; ++h) {
      UprightTransform fit;
      fit.yaw = 2.0 * kPi * h / options_.headings;
      fit.translation = centroid - fit.Apply(shape_centroid);
      const double score = Icp(&fit);
      if (score < score_) score_ = score, body_ = fit;
    }
    if (score_ >= 1e299) return false;
    placed_.resize(shape_.size());
    for (size_t k = 0; k < shape_.size(); ++k) placed_[k] = body_.Apply(set_.mean_shape[static_cast<size_t>(shape_[k])]);
    return true;
  }

  // Each segment onto its matched points: rigidly with three or more (the body's scale kept),
  // shifted with fewer; then matched again.
  void FitSegments() {
    std::vector<Eigen::Vector3d> body_placed = placed_;
    Eigen::MatrixXd cost;
    for (int round = 0; round < options_.segment_rounds; ++round) {
      const double gate = round == 0 ? options_.search_gate_mm : 2.0 * options_.gate_mm;
      const std::vector<int> match = Match(placed_, points_, gate, &cost);
      std::vector<int> point_of(shape_.size(), -1);
      std::vector<int> k_of_marker(set_.NumMarkers(), -1);
      for (size_t k = 0; k < shape_.size(); ++k) k_of_marker[static_cast<size_t>(shape_[k])] = static_cast<int>(k);
      // Names already given are the segments' correspondences; the match fills in the rest.
      std::vector<char> known_point(points_.size(), 0);
      if (known_ != nullptr)
        for (size_t p = 0; p < points_.size(); ++p) {
          const int m = (*known_)[p];
          if (m < 0 || static_cast<size_t>(m) >= k_of_marker.size() || k_of_marker[static_cast<size_t>(m)] < 0) continue;
          point_of[static_cast<size_t>(k_of_marker[static_cast<size_t>(m)])] = static_cast<int>(p);
          known_point[p] = 1;
        }
      for (size_t p = 0; p < points_.size(); ++p)
        if (match[p] >= 0 && !known_point[p] && point_of[static_cast<size_t>(match[p])] < 0)
          point_of[static_cast<size_t>(match[p])] = static_cast<int>(p);
      for (const std::vector<int>& segment : set_.segments) {
        std::vector<Eigen::Vector3d> source, target;
        std::vector<size_t> members;
        for (int m : segment) {
          const int k = k_of_marker[static_cast<size_t>(m)];
          if (k < 0) continue;
          members.push_back(static_cast<size_t>(k));
          if (point_of[static_cast<size_t>(k)] >= 0) {
            source.push_back(body_placed[static_cast<size_t>(k)]);
            target.push_back(points_[static_cast<size_t>(point_of[static_cast<size_t>(k)])]);
          }
        }
        if (source.empty()) continue;
        bool rigid = false;
        if (source.size() >= 3) {
          try {
            const SimilarityTransform t = FitRigid(source, target);
            for (size_t k : members) placed_[k] = t.Apply(body_placed[k]);
            rigid = true;
          } catch (const std::invalid_argument&) {
            // collinear: shifted below
          }
        }
        if (rigid) continue;
        Eigen::Vector3d shift = Eigen::Vector3d::Zero();
        for (size_t i = 0; i < source.size(); ++i) shift += target[i] - source[i];
        shift /= static_cast<double>(source.size());
        for (size_t k : members) placed_[k] = body_placed[k] + shift;
      }
    }
  }

  // One to one between the points not yet named and the markers no known point holds; a point is
  // named only when no other of them comes near.
  void Name(const std::vector<int>* known, std::vector<int>* labels) const {
    std::vector<size_t> rows, cols;
    std::vector<char> held(set_.NumMarkers(), 0);
    for (size_t p = 0; p < points_.size(); ++p) {
      const int m = known != nullptr ? (*known)[p] : -1;
      if (m >= 0 && static_cast<size_t>(m) < held.size()) held[static_cast<size_t>(m)] = 1;
      else rows.push_back(p);
    }
    for (size_t k = 0; k < shape_.size(); ++k)
      if (!held[static_cast<size_t>(shape_[k])]) cols.push_back(k);
    Eigen::MatrixXd cost(static_cast<Eigen::Index>(rows.size()), static_cast<Eigen::Index>(cols.size()));
    for (size_t i = 0; i < rows.size(); ++i)
      for (size_t j = 0; j < cols.size(); ++j) cost(i, j) = (placed_[cols[j]] - points_[rows[i]]).norm();
    const std::vector<int> match = SolveAssignment(cost, options_.gate_mm);
    for (size_t i = 0; i < rows.size(); ++i) {
      if (match[i] < 0) continue;
      const double d = cost(i, match[i]);
      const double clear = std::max(options_.ambiguity_ratio * d, d + options_.margin_mm);
      bool ambiguous = false;
      for (Eigen::Index q = 0; q < cost.rows() && !ambiguous; ++q) ambiguous = q != static_cast<Eigen::Index>(i) && cost(q, match[i]) < clear;
      for (Eigen::Index k = 0; k < cost.cols() && !ambiguous; ++k) ambiguous = k != match[i] && cost(i, k) < clear;
      if (!ambiguous) (*labels)[rows[i]] = shape_[cols[static_cast<size_t>(match[i])]];
    }
  }

  const MarkerSet& set_;
  const std::vector<Eigen::Vector3d>& points_;
  const SetFitOptions& options_;
  const std::vector<int>* known_ = nullptr;  // names already given, per point (or null)
  std::vector<int> shape_;  // markers with a place in the mean shape
  UprightTransform body_;
  double score_ = 1e300;
  std::vector<Eigen::Vector3d> placed_;  // per shape marker
};

}  // namespace

void SetFitOptions::Check() const {
  const auto refuse = [](const std::string& field, double value, const std::string& rule) {
    throw std::invalid_argument("set fit " + field + ": " + std::to_string(value) + " " + rule);
  };
  if (!(gate_mm > 0.0 && gate_mm < 1e4)) refuse("gate_mm", gate_mm, "must be in (0, 10000)");
  if (!(search_gate_mm >= gate_mm && search_gate_mm < 1e4)) refuse("search_gate_mm", search_gate_mm, "must be in [gate_mm, 10000)");
  if (!(ambiguity_ratio >= 1.0 && ambiguity_ratio < 100.0)) refuse("ambiguity_ratio", ambiguity_ratio, "must be in [1, 100)");
  if (!(margin_mm >= 0.0 && margin_mm < 1e4)) refuse("margin_mm", margin_mm, "must be in [0, 10000)");
  if (headings < 1 || headings > 360) refuse("headings", headings, "must be 1-360");
  if (segment_rounds < 0 || segment_rounds > 20) refuse("segment_rounds", segment_rounds, "must be 0-20");
}

SetFit FitSetToFrame(const MarkerSet& set, const std::vector<Eigen::Vector3d>& points_z_up, const SetFitOptions& options,
                     const std::vector<int>* known) {
  options.Check();
  if (known != nullptr && known->size() != points_z_up.size()) throw std::invalid_argument("set fit: known names are not one per point");
  FrameFitter fitter(set, points_z_up, options);
  return fitter.Fit(known);
}

}  // namespace mocap

// Labelling a whole recording by a subject model (see subject_labeller.h).
#include "labels/subject_labeller.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <stdexcept>
#include <utility>

#include <Eigen/Geometry>
#include <fmt/format.h>

#include "geometry/rigid_fit.h"
#include "labels/marker_set_learning.h"
#include "util/assignment.h"

namespace mocap {
namespace {

constexpr size_t kMaxPartners = 6;  // the steadiest partners present place a name
constexpr int kMinInitVotes = 3;     // fitted frames a run's initial name needs at least

struct Run {
  size_t column = 0;
  size_t first = 0, last = 0;  // frame indices, inclusive
  int label = -1;
  int streak = 0;  // frames in a row, in the pass's direction, that broke its steady pairs
};

struct PairStats {
  double sum = 0.0, sum_squares = 0.0;
  int n = 0;
  double Mean() const { return sum / n; }
  double Sd() const { return std::sqrt(std::max(0.0, sum_squares / n - Mean() * Mean())); }
};

Eigen::Vector3d Nan() { return Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN()); }

class SubjectLabeller {
 public:
  SubjectLabeller(const MarkerTrajectories& in, MarkerSet set, const SubjectLabellerOptions& options)
      : in_(in), set_(std::move(set)), options_(options), n_(set_.NumMarkers()), columns_(in.NumMarkers()) {
    options_.Check();
    options_.fit.Check();
    set_.Index();
    for (size_t m = 0; m < n_; ++m) shape_markers_ += m < set_.mean_shape.size() && set_.mean_shape[m].allFinite();
    if (shape_markers_ < 3) throw std::invalid_argument("the marker set places fewer than 3 markers in its mean shape");
    const int up = options_.up_axis >= 0 ? options_.up_axis : DetectUpAxis(in_);
    to_z_ = UpToZ(up >= 0 ? up : 2);
    pairs_.resize(n_ * n_);
    snapshot_.assign(n_, std::vector<Eigen::Vector3d>(n_, Nan()));
    frame_pos_.assign(n_, Nan());
    holders_.resize(n_);
  }

  SubjectLabelling Label() {
    FindRuns();
    if (Initialise()) {
      LearnInitialFrames();
      Pass(+1);
      Pass(-1);
    }
    return Output();
  }

 private:
  // --- Stage 0: runs.
  void FindRuns() {
    run_at_.assign(in_.points.size(), -1);
    label_at_.assign(in_.points.size(), -1);
    processed_.assign(in_.NumFrames(), 0);
    std::vector<int64_t> open(columns_, -1);
    for (size_t f = 0; f < in_.NumFrames(); ++f)
      for (size_t c = 0; c < columns_; ++c) {
        if (!in_.Has(f, c)) {
          open[c] = -1;
          continue;
        }
        if (open[c] < 0) {
          open[c] = static_cast<int64_t>(runs_.size());
          runs_.push_back(Run{c, f, f, -1, 0});
        }
        runs_[static_cast<size_t>(open[c])].last = f;
        run_at_[f * columns_ + c] = open[c];
      }
  }

  // --- Stage 1: the set fitted to the first frames seen whole; runs named where all agree.
  bool Initialise() {
    std::map<size_t, int> best;
    size_t best_first = 0, start = 0;
    // Seen nearly whole: a few markers may be hidden in every frame (or never seen at all).
    const size_t whole = shape_markers_ - static_cast<size_t>(options_.init_missing_share * static_cast<double>(shape_markers_));
    for (int attempt = 0; attempt < options_.init_attempts; ++attempt) {
      std::vector<size_t> frames;
      for (size_t f = start; f < in_.NumFrames() && static_cast<int>(frames.size()) < options_.init_frames; ++f) {
        if (!frames.empty() && f < frames.back() + static_cast<size_t>(options_.init_spacing)) continue;
        size_t present = 0;
        for (size_t c = 0; c < columns_; ++c) present += in_.Has(f, c);
        if (present >= whole) frames.push_back(f);
      }
      if (frames.size() < static_cast<size_t>(kMinInitVotes)) break;  // one fit agrees with itself
      std::map<size_t, int> agreed = FitWindow(frames);
      Decide(fmt::format("initialisation: frames {}-{}: {} names agree over {} fitted frames", in_.frame_numbers[frames.front()],
                         in_.frame_numbers[frames.back()], agreed.size(), frames.size()));
      if (agreed.size() > best.size()) best = std::move(agreed), best_first = frames.front();
      if (static_cast<double>(best.size()) >= options_.init_min_share * static_cast<double>(shape_markers_)) break;
      start = frames.back() + 1;
    }
    if (best.size() < 3) {
      Decide("initialisation: no window where the set is seen nearly whole and 3 names agree: nothing named");
      return false;
    }
    for (const auto& [r, label] : best) {
      runs_[r].label = label;
      holders_[static_cast<size_t>(label)].push_back(r);
      Decide(fmt::format("initialisation: {} is {} (frames {}-{}; fitted frames agree)", in_.names[runs_[r].column],
                         set_.names[static_cast<size_t>(label)], in_.frame_numbers[runs_[r].first],
                         in_.frame_numbers[runs_[r].last]));
    }
    init_frame_ = best_first;
    init_names_ = best.size();
    return true;
  }

  // Per run, the name at least init_agreement of the fitted frames it is in gave it (three of
  // them at least), and no name given to two runs that overlap in time.
  std::map<size_t, int> FitWindow(const std::vector<size_t>& frames) {
    std::map<size_t, std::map<int, int>> votes;  // run -> label (-1: none) -> fitted frames
    std::vector<Eigen::Vector3d> points;
    std::vector<size_t> runs;
    for (size_t f : frames) {
      points.clear(), runs.clear();
      for (size_t c = 0; c < columns_; ++c)
        if (run_at_[f * columns_ + c] >= 0) {
          points.push_back(to_z_ * in_.At(f, c));
          runs.push_back(static_cast<size_t>(run_at_[f * columns_ + c]));
        }
      const SetFit fit = FitSetToFrame(set_, points, options_.fit);
      for (size_t p = 0; p < points.size(); ++p) ++votes[runs[p]][fit.labels[p]];
    }
    std::map<size_t, int> agreed;
    for (const auto& [r, tally] : votes) {
      int total = 0, best = -1, best_votes = 0;
      for (const auto& [label, n] : tally) {
        total += n;
        if (label >= 0 && n > best_votes) best = label, best_votes = n;
      }
      if (best >= 0 && best_votes >= kMinInitVotes && best_votes >= options_.init_agreement * total) agreed[r] = best;
    }
    std::vector<size_t> clash;
    for (auto x = agreed.begin(); x != agreed.end(); ++x)
      for (auto y = std::next(x); y != agreed.end(); ++y)
        if (x->second == y->second && Overlap(runs_[x->first], runs_[y->first])) clash.push_back(x->first), clash.push_back(y->first);
    for (size_t r : clash) agreed.erase(r);
    return agreed;
  }

  // The subject's own distances over the initialisation's frames, before the passes judge by them.
  void LearnInitialFrames() {
    const size_t until = std::min(in_.NumFrames(),
                                  init_frame_ + static_cast<size_t>(options_.init_frames * options_.init_spacing) + 1);
    for (size_t f = init_frame_; f < until; ++f) {
      Gather(f);
      Learn(f);
    }
    last_frame_.assign(n_, -1);
  }

  // --- Stages 2 and 3: frame by frame from the initialisation, forward, then backward.
  void Pass(int direction) {
    last_frame_.assign(n_, -1);
    prev_frame_.assign(n_, -1);
    last_pos_.assign(n_, Nan());
    prev_pos_.assign(n_, Nan());
    for (Run& run : runs_) run.streak = 0;
    last_refit_ = -1;
    if (direction > 0) {
      for (size_t f = init_frame_; f < in_.NumFrames(); ++f) Step(f, direction);
    } else {
      SeedLastSeen(init_frame_);
      for (size_t f = init_frame_; f-- > 0;) Step(f, direction);
    }
  }

  void Step(size_t f, int direction) {
    Gather(f);
    CheckNamed(f, direction);
    NameFree(f, direction);
    Refit(f, direction);
    for (size_t i = 0; i < points_.size(); ++i)
      if (labels_[i] >= 0) label_at_[f * columns_ + cols_[i]] = labels_[i];
    Learn(f);
    processed_[f] = 1;
  }

  void Gather(size_t f) {
    points_.clear(), cols_.clear(), runs_now_.clear(), labels_.clear();
    std::fill(point_of_label_.begin(), point_of_label_.end(), -1);
    point_of_label_.resize(n_, -1);
    for (size_t c = 0; c < columns_; ++c) {
      const int64_t r = run_at_[f * columns_ + c];
      if (r < 0) continue;
      int label = runs_[static_cast<size_t>(r)].label;
      if (label >= 0 && point_of_label_[static_cast<size_t>(label)] >= 0) label = -1;  // never two holders in a frame
      if (label >= 0) point_of_label_[static_cast<size_t>(label)] = static_cast<int>(points_.size());
      points_.push_back(in_.At(f, c));
      cols_.push_back(c);
      runs_now_.push_back(static_cast<size_t>(r));
      labels_.push_back(label);
    }
  }

  bool Steady(int a, int b) const {
    const PairStats& s = Pair(a, b);
    return s.n >= options_.min_pair_frames && s.Sd() <= options_.steady_sd_mm && s.Mean() <= options_.max_pair_mm;
  }
  const PairStats& Pair(int a, int b) const {
    return pairs_[static_cast<size_t>(std::min(a, b)) * n_ + static_cast<size_t>(std::max(a, b))];
  }
  bool Breaks(int a, int b, double distance) const {
    const PairStats& s = Pair(a, b);
    return std::abs(distance - s.Mean()) > options_.break_mm + 4.0 * s.Sd();
  }

  // Steady pairs of `label` at `at` against the named points of this frame (skipping point `self`).
  std::pair<int, int> Count(int label, const Eigen::Vector3d& at, int self) const {
    int checks = 0, breaks = 0;
    for (size_t q = 0; q < points_.size(); ++q) {
      const int b = labels_[q];
      if (static_cast<int>(q) == self || b < 0 || b == label || !Steady(label, b)) continue;
      ++checks;
      breaks += Breaks(label, b, (at - points_[q]).norm());
    }
    return {checks, breaks};
  }

  // Named points breaking most of their steady pairs lose their name in this frame (the worst
  // first: one swapped point breaks its honest partners' pairs too); a run that does so for
  // break_frames frames in a row loses the name from where it broke.
  void CheckNamed(size_t f, int direction) {
    for (size_t i = 0; i < points_.size(); ++i) {
      const int a = labels_[i];
      if (a < 0) continue;
      const long last = last_frame_[static_cast<size_t>(a)], prev = prev_frame_[static_cast<size_t>(a)];
      if (last < 0 || prev < 0 || std::abs(static_cast<long>(f) - last) != 1 || std::abs(last - prev) != 1) continue;
      const Eigen::Vector3d predicted = 2.0 * last_pos_[static_cast<size_t>(a)] - prev_pos_[static_cast<size_t>(a)];
      const double jump = (points_[i] - predicted).norm();
      if (jump <= options_.jump_mm) continue;
      // Noise or a fast limb moves a point off its prediction too; a join puts another point
      // where the name was going.
      bool nearer = false;
      for (size_t q = 0; q < points_.size() && !nearer; ++q) nearer = q != i && 2.0 * (points_[q] - predicted).norm() < jump;
      if (!nearer) continue;
      Run& run = runs_[runs_now_[i]];
      if (direction > 0 ? f == run.first : f == run.last) {
        run.label = -1;
      } else {
        runs_now_[i] = Split(runs_now_[i], f, direction);
      }
      point_of_label_[static_cast<size_t>(a)] = -1;
      labels_[i] = -1;
      Decide(fmt::format("frame {}: {} loses {} from here on (it jumps {:.0f} mm from where the name was going, "
                         "another point is there: the tracker joined two markers)",
                         in_.frame_numbers[f], in_.names[cols_[i]], set_.names[static_cast<size_t>(a)], jump));
    }
    std::vector<char> broken(points_.size(), 0);
    while (true) {
      int worst = -1, worst_breaks = 0;
      for (size_t i = 0; i < points_.size(); ++i) {
        if (labels_[i] < 0) continue;
        const auto [checks, breaks] = Count(labels_[i], points_[i], static_cast<int>(i));
        if (checks >= 2 && 2 * breaks > checks && breaks > worst_breaks) worst = static_cast<int>(i), worst_breaks = breaks;
      }
      if (worst < 0) break;
      broken[static_cast<size_t>(worst)] = 1;
      point_of_label_[static_cast<size_t>(labels_[static_cast<size_t>(worst)])] = -1;
      labels_[static_cast<size_t>(worst)] = -1;
    }
    for (size_t i = 0; i < points_.size(); ++i) {
      Run& run = runs_[runs_now_[i]];
      if (run.label < 0) continue;
      if (!broken[i]) {
        run.streak = 0;
        continue;
      }
      ++frames_dropped_;
      if (++run.streak < options_.break_frames) continue;
      const size_t back = static_cast<size_t>(run.streak - 1);
      const size_t from = direction > 0 ? f - back : f + back;
      const int label = run.label;
      const bool whole = direction > 0 ? from == run.first : from == run.last;
      if (whole) {
        run.label = -1;
        run.streak = 0;
      } else {
        runs_now_[i] = Split(runs_now_[i], from, direction);
      }
      Decide(fmt::format("frame {}: {} loses {} from frame {} on (broke its steady pairs {} frames in a row: a swap)",
                         in_.frame_numbers[f], in_.names[cols_[i]], set_.names[static_cast<size_t>(label)],
                         in_.frame_numbers[from], options_.break_frames));
    }
  }

  // Where a name no run holds now should be: placed by its steady partners, or where it was last
  // seen. Returns the gate, or 0 when it cannot be placed.
  double Place(int a, size_t f, Eigen::Vector3d* at, const char** how) const {
    const std::vector<Eigen::Vector3d>& snap = snapshot_[static_cast<size_t>(a)];
    if (snap[static_cast<size_t>(a)].allFinite()) {
      std::vector<std::pair<double, int>> partners;
      for (size_t b = 0; b < n_; ++b)
        if (static_cast<int>(b) != a && point_of_label_[b] >= 0 && snap[b].allFinite() && Steady(a, static_cast<int>(b)))
          partners.push_back({Pair(a, static_cast<int>(b)).Sd(), static_cast<int>(b)});
      std::sort(partners.begin(), partners.end());
      if (partners.size() > kMaxPartners) partners.resize(kMaxPartners);
      std::vector<Eigen::Vector3d> then, now;
      for (const auto& [sd, b] : partners) {
        then.push_back(snap[static_cast<size_t>(b)]);
        now.push_back(points_[static_cast<size_t>(point_of_label_[static_cast<size_t>(b)])]);
      }
      if (now.size() >= 3) {
        try {
          const SimilarityTransform t = FitRigid(then, now);
          if (AlignmentRms(t, then, now) <= 0.5 * options_.partner_gate_mm) {
            *at = t.Apply(snap[static_cast<size_t>(a)]);
            *how = "placed by its partners";
            return options_.partner_gate_mm;
          }
        } catch (const std::invalid_argument&) {
          // collinear partners: the two-point rule below
        }
      }
      if (now.size() >= 2) {
        const Eigen::Vector3d u = (then[1] - then[0]).normalized(), v = (now[1] - now[0]).normalized();
        const Eigen::Matrix3d r = Eigen::Quaterniond::FromTwoVectors(u, v).toRotationMatrix();
        *at = r * (snap[static_cast<size_t>(a)] - 0.5 * (then[0] + then[1])) + 0.5 * (now[0] + now[1]);
        *how = "placed by two partners";
        return options_.partner_gate_mm;
      }
    }
    const long last = last_frame_[static_cast<size_t>(a)];
    if (last < 0) return 0.0;
    const double gap = std::abs(static_cast<double>(f) - static_cast<double>(last));
    if (gap > options_.hold_frames) return 0.0;
    *at = last_pos_[static_cast<size_t>(a)];
    const long prev = prev_frame_[static_cast<size_t>(a)];
    if (prev >= 0 && std::abs(last - prev) == 1) *at += (last_pos_[static_cast<size_t>(a)] - prev_pos_[static_cast<size_t>(a)]) * gap;
    *how = "where it was last seen";
    return options_.partner_gate_mm + options_.hold_gate_mm_per_frame * gap;
  }

  // Names no run holds, to unnamed points: one to one within the gates, only where no other
  // point or name comes near and the point keeps the name's steady pairs.
  void NameFree(size_t f, int direction) {
    std::vector<char> held(n_, 0);
    for (size_t i = 0; i < points_.size(); ++i)
      if (runs_[runs_now_[i]].label >= 0) held[static_cast<size_t>(runs_[runs_now_[i]].label)] = 1;
    std::vector<int> free_points, names;
    std::vector<Eigen::Vector3d> placed;
    std::vector<double> gates;
    std::vector<const char*> hows;
    for (size_t i = 0; i < points_.size(); ++i)
      if (runs_[runs_now_[i]].label < 0) free_points.push_back(static_cast<int>(i));
    if (free_points.empty()) return;
    for (size_t a = 0; a < n_; ++a) {
      if (held[a]) continue;
      Eigen::Vector3d at;
      const char* how = "";
      const double gate = Place(static_cast<int>(a), f, &at, &how);
      if (gate <= 0.0) continue;
      names.push_back(static_cast<int>(a)), placed.push_back(at), gates.push_back(gate), hows.push_back(how);
    }
    if (names.empty()) return;
    Eigen::MatrixXd cost(static_cast<Eigen::Index>(free_points.size()), static_cast<Eigen::Index>(names.size()));
    for (size_t i = 0; i < free_points.size(); ++i)
      for (size_t k = 0; k < names.size(); ++k)
        cost(i, k) = (points_[static_cast<size_t>(free_points[i])] - placed[k]).norm();
    Eigen::MatrixXd scaled = cost;
    for (size_t k = 0; k < names.size(); ++k) scaled.col(static_cast<Eigen::Index>(k)) /= gates[k];
    const std::vector<int> match = SolveAssignment(scaled, 1.0);
    for (size_t i = 0; i < free_points.size(); ++i) {
      if (match[i] < 0) continue;
      const size_t k = static_cast<size_t>(match[i]);
      const int p = free_points[i], a = names[k];
      const double d = cost(i, match[i]);
      const double clear = std::max(options_.ambiguity_ratio * d, d + options_.margin_mm);
      bool ambiguous = false;
      for (size_t j = 0; j < free_points.size() && !ambiguous; ++j) ambiguous = j != i && cost(j, match[i]) < clear;
      for (Eigen::Index x = 0; x < cost.cols() && !ambiguous; ++x) ambiguous = x != match[i] && cost(i, x) < clear;
      if (ambiguous) continue;
      const auto [checks, breaks] = Count(a, points_[static_cast<size_t>(p)], p);
      if (4 * breaks > checks) continue;
      size_t r = runs_now_[static_cast<size_t>(p)];
      if (!NameRun(&r, a, f, direction)) continue;
      runs_now_[static_cast<size_t>(p)] = r;
      labels_[static_cast<size_t>(p)] = a;
      point_of_label_[static_cast<size_t>(a)] = p;
      Decide(fmt::format("frame {}: {} is {} ({}, {:.1f} mm off; the next point or name {:.0f} mm or more away; "
                         "{} of {} steady pairs hold)",
                         in_.frame_numbers[f], in_.names[cols_[static_cast<size_t>(p)]], set_.names[static_cast<size_t>(a)],
                         hows[k], d, clear, checks - breaks, checks));
    }
  }

  // Names that neither partners nor a last place can give: the set's shape placed on the names
  // this frame holds, now and then, for the unnamed points.
  void Refit(size_t f, int direction) {
    if (last_refit_ >= 0 && std::abs(static_cast<long>(f) - last_refit_) < options_.refit_frames) return;
    std::vector<char> held(n_, 0);
    bool unnamed = false;
    for (size_t i = 0; i < points_.size(); ++i) {
      const int label = runs_[runs_now_[i]].label;
      if (label >= 0) held[static_cast<size_t>(label)] = 1;
      unnamed = unnamed || label < 0;
    }
    if (!unnamed || std::count(held.begin(), held.end(), 1) == static_cast<long>(n_)) return;
    last_refit_ = static_cast<long>(f);
    std::vector<Eigen::Vector3d> canonical(points_.size());
    for (size_t i = 0; i < points_.size(); ++i) canonical[i] = to_z_ * points_[i];
    SetFitOptions refit = options_.fit;
    refit.gate_mm = options_.refit_gate_mm;
    refit.search_gate_mm = std::max(refit.search_gate_mm, refit.gate_mm);
    const SetFit fit = FitSetToFrame(set_, canonical, refit, &labels_);
    size_t named = 0;
    for (size_t i = 0; i < points_.size(); ++i) named += labels_[i] >= 0;
    if (named < 4) return;
    for (size_t i = 0; i < points_.size(); ++i) {
      const int a = fit.labels[i];
      size_t r = runs_now_[i];
      if (a < 0 || held[static_cast<size_t>(a)] || runs_[r].label >= 0) continue;
      auto [vote, added] = refit_votes_.emplace(r, std::make_pair(a, 0));
      if (vote->second.first != a) vote->second = {a, 0};
      if (++vote->second.second < options_.refit_confirm) continue;
      const auto [checks, breaks] = Count(a, points_[i], static_cast<int>(i));
      if (4 * breaks > checks) continue;
      if (!NameRun(&r, a, f, direction)) continue;
      runs_now_[i] = r;
      labels_[i] = a;
      held[static_cast<size_t>(a)] = 1;
      point_of_label_[static_cast<size_t>(a)] = static_cast<int>(i);
      Decide(fmt::format("frame {}: {} is {} (the set's shape placed on the {} names given: {} fits in a row agree; "
                         "{} of {} steady pairs hold)",
                         in_.frame_numbers[f], in_.names[cols_[i]], set_.names[static_cast<size_t>(a)], named,
                         options_.refit_confirm, checks - breaks, checks));
    }
  }

  bool Free(int label, const Run& run, size_t self) const {
    for (size_t h : holders_[static_cast<size_t>(label)])
      if (h != self && runs_[h].label == label && Overlap(runs_[h], run)) return false;
    return true;
  }
  static bool Overlap(const Run& x, const Run& y) { return x.first <= y.last && y.first <= x.last; }

  // Gives run *r the name from frame f on (in the pass's direction) and over the frames already
  // passed where it keeps its steady pairs; where the name is not free over the whole run, only
  // the piece from f on takes it (*r becomes that piece).
  bool NameRun(size_t* r, int label, size_t f, int direction) {
    if (!Free(label, runs_[*r], *r)) {
      const bool at_start = direction > 0 ? f == runs_[*r].first : f == runs_[*r].last;
      if (at_start) return false;
      const size_t piece = Split(*r, f, direction);
      if (!Free(label, runs_[piece], piece)) return false;
      *r = piece;
    }
    Run& run = runs_[*r];
    run.label = label;
    run.streak = 0;
    holders_[static_cast<size_t>(label)].push_back(*r);
    // The frames already passed, from f back, while the run keeps its pairs there.
    int streak = 0;
    for (long g = static_cast<long>(f) - direction;
         g >= static_cast<long>(run.first) && g <= static_cast<long>(run.last) && processed_[static_cast<size_t>(g)];
         g -= direction) {
      const size_t frame = static_cast<size_t>(g);
      if (!PassedFrameKeeps(frame, run.column, label)) {
        if (++streak >= options_.break_frames) {
          const long from = g + direction * (streak - 1);
          Split(*r, static_cast<size_t>(from), -direction);
          break;
        }
        continue;
      }
      streak = 0;
      label_at_[frame * columns_ + run.column] = label;
    }
    return true;
  }

  // Whether the point of `column` in a passed frame keeps `label`'s steady pairs with that
  // frame's names (and nothing else carries the name there).
  bool PassedFrameKeeps(size_t f, size_t column, int label) const {
    const Eigen::Vector3d at = in_.At(f, column);
    int checks = 0, breaks = 0;
    for (size_t c = 0; c < columns_; ++c) {
      const int b = label_at_[f * columns_ + c];
      if (c == column || b < 0) continue;
      if (b == label) return false;
      if (!Steady(label, b)) continue;
      ++checks;
      breaks += Breaks(label, b, (at - in_.At(f, c)).norm());
    }
    return !(checks >= 2 && 2 * breaks > checks);
  }

  // Cuts run r at frame `from`: the part from `from` on in `direction` becomes a new, unnamed
  // run, returned; r keeps the rest.
  size_t Split(size_t r, size_t from, int direction) {
    Run piece = runs_[r];
    piece.label = -1;
    piece.streak = 0;
    if (direction > 0) {
      piece.first = from;
      runs_[r].last = from - 1;
    } else {
      piece.last = from;
      runs_[r].first = from + 1;
    }
    const size_t index = runs_.size();
    runs_.push_back(piece);
    for (size_t g = piece.first; g <= piece.last; ++g) {
      run_at_[g * columns_ + piece.column] = static_cast<int64_t>(index);
      label_at_[g * columns_ + piece.column] = -1;
    }
    return index;
  }

  // What this frame teaches: the subject's distances, where each name's partners stood, where
  // each name was last seen.
  void Learn(size_t f) {
    std::fill(frame_pos_.begin(), frame_pos_.end(), Nan());
    std::vector<int> named;
    for (size_t i = 0; i < points_.size(); ++i)
      if (labels_[i] >= 0) frame_pos_[static_cast<size_t>(labels_[i])] = points_[i], named.push_back(labels_[i]);
    for (size_t x = 0; x < named.size(); ++x)
      for (size_t y = x + 1; y < named.size(); ++y) {
        const int a = std::min(named[x], named[y]), b = std::max(named[x], named[y]);
        PairStats& s = pairs_[static_cast<size_t>(a) * n_ + static_cast<size_t>(b)];
        const double d = (frame_pos_[static_cast<size_t>(a)] - frame_pos_[static_cast<size_t>(b)]).norm();
        s.sum += d, s.sum_squares += d * d, ++s.n;
      }
    for (int a : named) {
      snapshot_[static_cast<size_t>(a)] = frame_pos_;
      if (last_frame_.empty()) continue;
      prev_frame_[static_cast<size_t>(a)] = last_frame_[static_cast<size_t>(a)];
      prev_pos_[static_cast<size_t>(a)] = last_pos_[static_cast<size_t>(a)];
      last_frame_[static_cast<size_t>(a)] = static_cast<long>(f);
      last_pos_[static_cast<size_t>(a)] = frame_pos_[static_cast<size_t>(a)];
    }
  }

  void SeedLastSeen(size_t f) {
    for (size_t c = 0; c < columns_; ++c) {
      const int a = label_at_[f * columns_ + c];
      if (a < 0) continue;
      last_frame_[static_cast<size_t>(a)] = static_cast<long>(f);
      last_pos_[static_cast<size_t>(a)] = in_.At(f, c);
    }
  }

  void Decide(std::string line) {
    ++decisions_made_;
    if (decisions_.size() < options_.max_decisions) decisions_.push_back(std::move(line));
  }

  // Columns: the names placed, in the set's order, then the input columns left with data.
  SubjectLabelling Output() {
    SubjectLabelling out;
    std::vector<int> holders(n_, 0);
    for (size_t f = 0; f < in_.NumFrames(); ++f) {
      for (size_t c = 0; c < columns_; ++c)
        if (label_at_[f * columns_ + c] >= 0) ++holders[static_cast<size_t>(label_at_[f * columns_ + c])];
      for (size_t c = 0; c < columns_; ++c) {
        int& label = label_at_[f * columns_ + c];
        if (label >= 0 && holders[static_cast<size_t>(label)] > 1) label = -1, ++out.frame_names_dropped;
      }
      std::fill(holders.begin(), holders.end(), 0);
    }
    std::vector<int> column_of_label(n_, -1), leftover_column(columns_, -1);
    for (size_t i = 0; i < label_at_.size(); ++i) {
      if (run_at_[i] < 0) continue;
      if (label_at_[i] >= 0) column_of_label[static_cast<size_t>(label_at_[i])] = 0;
      else leftover_column[i % columns_] = 0;
    }
    MarkerTrajectories& named = out.named;
    named.rate_hz = in_.rate_hz;
    for (size_t a = 0; a < n_; ++a)
      if (column_of_label[a] == 0) column_of_label[a] = static_cast<int>(named.names.size()), named.names.push_back(set_.names[a]);
    out.names_placed = named.names.size();
    for (size_t c = 0; c < columns_; ++c)
      if (leftover_column[c] == 0) leftover_column[c] = static_cast<int>(named.names.size()), named.names.push_back(in_.names[c]);
    for (size_t f = 0; f < in_.NumFrames(); ++f) {
      const size_t row = named.AddFrame(in_.frame_numbers[f]);
      for (size_t c = 0; c < columns_; ++c) {
        if (run_at_[f * columns_ + c] < 0) continue;
        const int label = label_at_[f * columns_ + c];
        const int column = label >= 0 ? column_of_label[static_cast<size_t>(label)] : leftover_column[c];
        named.At(row, static_cast<size_t>(column)) = in_.At(f, c);
        ++out.points;
        out.named_points += label >= 0;
      }
    }
    out.runs = runs_.size();
    out.named_runs = static_cast<size_t>(std::count_if(runs_.begin(), runs_.end(), [](const Run& r) { return r.label >= 0; }));
    out.frame_names_dropped += frames_dropped_;
    out.init_frame = init_names_ > 0 ? static_cast<long>(init_frame_) : -1;
    out.init_names = init_names_;
    out.decisions_made = decisions_made_;
    out.decisions = std::move(decisions_);
    return out;
  }

  const MarkerTrajectories& in_;
  MarkerSet set_;
  SubjectLabellerOptions options_;
  const size_t n_, columns_;
  size_t shape_markers_ = 0;
  Eigen::Matrix3d to_z_ = Eigen::Matrix3d::Identity();
  std::vector<Run> runs_;
  std::vector<int64_t> run_at_;  // per (frame, column): run, -1
  std::vector<int> label_at_;    // per (frame, column): the name written, -1
  std::vector<char> processed_;
  std::vector<std::vector<size_t>> holders_;  // per name: runs that were given it
  size_t init_frame_ = 0, init_names_ = 0;
  // The subject's own model.
  std::vector<PairStats> pairs_;                        // per a * n + b, a < b
  std::vector<std::vector<Eigen::Vector3d>> snapshot_;  // per name: every name's place the last frame it was named
  std::vector<long> last_frame_, prev_frame_;
  std::vector<Eigen::Vector3d> last_pos_, prev_pos_;
  // The frame in hand.
  std::vector<Eigen::Vector3d> points_, frame_pos_;
  std::vector<size_t> cols_, runs_now_;
  std::vector<int> labels_, point_of_label_;
  long last_refit_ = -1;
  std::map<size_t, std::pair<int, int>> refit_votes_;  // run -> (name the fits gave, fits in a row)
  size_t frames_dropped_ = 0;
  size_t decisions_made_ = 0;
  std::vector<std::string> decisions_;
};

}  // namespace

void SubjectLabellerOptions::Check() const {
  const auto refuse = [](const std::string& field, double value, const std::string& rule) {
    throw std::invalid_argument("labelling " + field + ": " + fmt::format("{}", value) + " " + rule);
  };
  if (up_axis < -1 || up_axis > 2) refuse("up_axis", up_axis, "must be 0, 1, 2 or -1");
  if (init_frames < 1 || init_frames > 100) refuse("init_frames", init_frames, "must be 1-100");
  if (init_spacing < 1 || init_spacing > 10000) refuse("init_spacing", init_spacing, "must be 1-10000");
  if (!(init_agreement > 0.5 && init_agreement <= 1.0)) refuse("init_agreement", init_agreement, "must be in (0.5, 1]");
  if (init_attempts < 1 || init_attempts > 1000) refuse("init_attempts", init_attempts, "must be 1-1000");
  if (!(init_min_share > 0.0 && init_min_share <= 1.0)) refuse("init_min_share", init_min_share, "must be in (0, 1]");
  if (!(init_missing_share >= 0.0 && init_missing_share <= 0.5))
    refuse("init_missing_share", init_missing_share, "must be in [0, 0.5]");
  if (!(partner_gate_mm > 0.0 && partner_gate_mm < 1e4)) refuse("partner_gate_mm", partner_gate_mm, "must be in (0, 10000)");
  if (!(hold_gate_mm_per_frame >= 0.0 && hold_gate_mm_per_frame < 1e4))
    refuse("hold_gate_mm_per_frame", hold_gate_mm_per_frame, "must be in [0, 10000)");
  if (hold_frames < 0 || hold_frames > 100000) refuse("hold_frames", hold_frames, "must be 0-100000");
  if (!(ambiguity_ratio >= 1.0 && ambiguity_ratio < 100.0)) refuse("ambiguity_ratio", ambiguity_ratio, "must be in [1, 100)");
  if (!(margin_mm >= 0.0 && margin_mm < 1e4)) refuse("margin_mm", margin_mm, "must be in [0, 10000)");
  if (!(steady_sd_mm > 0.0 && steady_sd_mm < 1e3)) refuse("steady_sd_mm", steady_sd_mm, "must be in (0, 1000)");
  if (!(max_pair_mm > 0.0 && max_pair_mm < 1e5)) refuse("max_pair_mm", max_pair_mm, "must be in (0, 100000)");
  if (!(break_mm > 0.0 && break_mm < 1e4)) refuse("break_mm", break_mm, "must be in (0, 10000)");
  if (break_frames < 1 || break_frames > 10000) refuse("break_frames", break_frames, "must be 1-10000");
  if (!(jump_mm > 0.0 && jump_mm < 1e5)) refuse("jump_mm", jump_mm, "must be in (0, 100000)");
  if (refit_frames < 1 || refit_frames > 100000) refuse("refit_frames", refit_frames, "must be 1-100000");
  if (refit_confirm < 1 || refit_confirm > 100) refuse("refit_confirm", refit_confirm, "must be 1-100");
  if (!(refit_gate_mm > 0.0 && refit_gate_mm < 1e4)) refuse("refit_gate_mm", refit_gate_mm, "must be in (0, 10000)");
  if (min_pair_frames < 2 || min_pair_frames > 100000) refuse("min_pair_frames", min_pair_frames, "must be 2-100000");
}

SubjectLabelling LabelSubject(const MarkerTrajectories& in, const MarkerSet& set, const SubjectLabellerOptions& options) {
  SubjectLabeller labeller(in, set, options);
  return labeller.Label();
}

}  // namespace mocap

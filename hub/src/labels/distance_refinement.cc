// The offline labeller's refinement of names by distances (see distance_refinement.h).
#include "labels/distance_refinement.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "util/assignment.h"

namespace mocap {

double PairCost(const MarkerSet& set, int a, int b, const RunPair& pair, double relative) {
  if (a < 0 || b < 0 || pair.frames < 10) return 0.0;
  const MarkerDistance* d = set.Distance(a, b);
  if (d == nullptr) return 0.0;
  // Another subject (a loose fit): only pairs steady in the set compare; how far apart two
  // joints' markers swing depends on the activity and the body, their rigidity does not.
  if (relative > 0.05 && d->sd > 5.0) return 0.0;
  // Both how long the distance is and how much it varies: a pair that is steady in the set must
  // be steady in the data too (rigidity does not change from one subject to another).
  const double spread = d->sd + 3.0 + relative * d->mean;
  const double z_mean = (pair.mean - d->mean) / (spread + pair.sd);
  const double z_sd = (pair.sd - d->sd) / (d->sd + 3.0);
  return std::min(z_mean * z_mean + z_sd * z_sd, 25.0);
}

void DistanceRefinementOptions::Check() const {
  const auto refuse = [](const char* field, double value, const char* rule) {
    throw std::invalid_argument(std::string(field) + ": " + std::to_string(value) + " " + rule);
  };
  if (max_runs < 2) refuse("max_runs", static_cast<double>(max_runs), "must be >= 2");
  if (!(unnamed_pair_cost > 0.0 && unnamed_pair_cost <= 25.0)) refuse("unnamed_pair_cost", unnamed_pair_cost, "not in (0, 25]");
  if (!(ambiguity_margin >= 0.0 && ambiguity_margin <= 25.0)) refuse("ambiguity_margin", ambiguity_margin, "not in [0, 25]");
  if (!(clear_share > 0.5 && clear_share <= 1.0)) refuse("clear_share", clear_share, "not in (0.5, 1]");
  if (!(min_frame_votes >= 1.0)) refuse("min_frame_votes", min_frame_votes, "must be >= 1");
}

DistanceRefinement::DistanceRefinement(const MarkerTrajectories& in, const MarkerSet& set,
                                       const std::vector<SegmentAnchors>& anchors, const std::vector<int64_t>& run_at,
                                       std::vector<Run>* runs, const DistanceRefinementOptions& options)
    : in_(in), set_(set), anchors_(anchors), run_at_(run_at), runs_(*runs), options_((options.Check(), options)),
      count_(runs->size()) {}

double DistanceRefinement::Refine(std::vector<std::vector<std::pair<size_t, size_t>>>* taken) {
  if (count_ < 2 || count_ > options_.max_runs) return 0.15;
  MeasurePairs();
  EstimateRelative();
  SettleLongRuns();
  LocalSearch();
  std::vector<char> confirmed(count_, 0);
  RenameBySegmentVotes(SegmentFrameVotes(), &confirmed);
  DropAmbiguous(confirmed);
  DropPoorFits();
  for (auto& t : *taken) t.clear();
  for (const Run& run : runs_)
    if (run.label >= 0) (*taken)[static_cast<size_t>(run.label)].push_back({run.first, run.last});
  return relative_;
}

void DistanceRefinement::MeasurePairs() {
  const size_t columns = in_.NumMarkers();
  pairs_.assign(count_ * count_, RunPair{});
  std::vector<double> sum(count_ * count_, 0.0), sum_squares(count_ * count_, 0.0);
  std::vector<int64_t> present;
  for (size_t f = 0; f < in_.NumFrames(); ++f) {
    present.clear();
    for (size_t c = 0; c < columns; ++c)
      if (run_at_[f * columns + c] >= 0) present.push_back(static_cast<int64_t>(c));
    for (size_t x = 0; x < present.size(); ++x)
      for (size_t y = x + 1; y < present.size(); ++y) {
        size_t i = static_cast<size_t>(run_at_[f * columns + static_cast<size_t>(present[x])]);
        size_t j = static_cast<size_t>(run_at_[f * columns + static_cast<size_t>(present[y])]);
        if (i > j) std::swap(i, j);
        const double d = (in_.At(f, static_cast<size_t>(present[x])) - in_.At(f, static_cast<size_t>(present[y]))).norm();
        sum[i * count_ + j] += d, sum_squares[i * count_ + j] += d * d, ++pairs_[i * count_ + j].frames;
      }
  }
  for (size_t i = 0; i < count_; ++i)
    for (size_t j = i + 1; j < count_; ++j) {
      RunPair& p = pairs_[i * count_ + j];
      if (p.frames == 0) continue;
      p.mean = sum[i * count_ + j] / p.frames;
      p.sd = std::sqrt(std::max(0.0, sum_squares[i * count_ + j] / p.frames - p.mean * p.mean));
      pairs_[j * count_ + i] = p;
    }
}

void DistanceRefinement::EstimateRelative() {
  relative_ = 0.1;
  std::vector<double> log_ratio;
  for (size_t i = 0; i < count_; ++i)
    for (size_t j = i + 1; j < count_; ++j) {
      const RunPair& p = Pair(i, j);
      const MarkerDistance* d = set_.Distance(runs_[i].label, runs_[j].label);
      if (p.frames >= 10 && d != nullptr && d->sd < 5.0 && p.sd < 5.0 && d->mean > 0.0)
        log_ratio.push_back(std::abs(std::log(p.mean / d->mean)));
    }
  if (log_ratio.size() >= 5) {
    std::nth_element(log_ratio.begin(), log_ratio.begin() + log_ratio.size() / 2, log_ratio.end());
    relative_ = std::clamp(3.0 * log_ratio[log_ratio.size() / 2], 0.01, 0.15);
  }
}

double DistanceRefinement::CostOf(size_t i, int label, size_t skip, int skip_label) const {
  double c = 0.0;
  for (size_t j = 0; j < count_; ++j) {
    if (j == i) continue;
    const int other = j == skip ? skip_label : runs_[j].label;
    c += PairCost(set_, label, other, Pair(i, j), relative_);
  }
  const auto it = runs_[i].support.find(label);
  const double share = runs_[i].total > 0.0 && it != runs_[i].support.end() ? it->second / runs_[i].total : 0.0;
  return c + 0.5 * (1.0 - share);
}

bool DistanceRefinement::FreeFor(int label, size_t i, size_t ignore) const {
  for (size_t j = 0; j < count_; ++j)
    if (j != i && j != ignore && runs_[j].label == label && runs_[i].first <= runs_[j].last &&
        runs_[j].first <= runs_[i].last)
      return false;
  return true;
}

// The pieces a swap left may overlap a run holding the name for a few frames (the frames two runs
// hold one name lose it in the output).
bool DistanceRefinement::FreeForExchange(int label, size_t i, size_t ignore) const {
  for (size_t j = 0; j < count_; ++j) {
    if (j == i || j == ignore || runs_[j].label != label) continue;
    const size_t first = std::max(runs_[i].first, runs_[j].first), last = std::min(runs_[i].last, runs_[j].last);
    if (first > last) continue;
    const size_t overlap = last - first + 1;
    if (overlap > options_.boundary_frames || 4 * overlap >= runs_[i].last - runs_[i].first + 1 ||
        4 * overlap >= runs_[j].last - runs_[j].first + 1)
      return false;
  }
  return true;
}

double DistanceRefinement::UnnamedCost(size_t i) const {
  double c = 0.0;
  for (size_t j = 0; j < count_; ++j)
    if (j != i && runs_[j].label >= 0 && Pair(i, j).frames >= 10) c += options_.unnamed_pair_cost;
  return c;
}

double DistanceRefinement::TotalCost() const {
  double c = 0.0;
  for (size_t i = 0; i < count_; ++i) {
    if (runs_[i].label < 0) {
      c += UnnamedCost(i);
      continue;
    }
    for (size_t j = i + 1; j < count_; ++j) c += PairCost(set_, runs_[i].label, runs_[j].label, Pair(i, j), relative_);
    const auto it = runs_[i].support.find(runs_[i].label);
    c += 0.5 * (1.0 - (runs_[i].total > 0.0 && it != runs_[i].support.end() ? it->second / runs_[i].total : 0.0));
  }
  return c;
}

// Long: half the recording or more (long runs overlap each other).
bool DistanceRefinement::IsShort(size_t i) const {
  return 2 * (runs_[i].last - runs_[i].first + 1) < in_.NumFrames();
}

// Short runs' names are set aside while the long runs settle theirs (a short run holding a name
// must not block the long runs' exchanges), then take names back where free. The long runs: each
// run's cost for every name given the others' names, solved one to one; kept while the total
// falls. This moves whole chains of names that single swaps cannot.
void DistanceRefinement::SettleLongRuns() {
  std::vector<int> short_label(count_, -1);
  for (size_t i = 0; i < count_; ++i)
    if (IsShort(i)) short_label[i] = runs_[i].label, runs_[i].label = -1;
  std::vector<size_t> long_runs;
  for (size_t i = 0; i < count_; ++i)
    if (!IsShort(i)) long_runs.push_back(i);
  const size_t labels = set_.NumMarkers();
  for (int round = 0; round < 10 && long_runs.size() >= 2; ++round) {
    Eigen::MatrixXd cost(long_runs.size(), labels);
    for (size_t x = 0; x < long_runs.size(); ++x) {
      const size_t i = long_runs[x];
      for (size_t a = 0; a < labels; ++a) {
        bool blocked = false;  // held by a short run overlapping this one
        for (size_t j = 0; j < count_ && !blocked; ++j)
          blocked = runs_[j].label == static_cast<int>(a) && IsShort(j) && runs_[i].first <= runs_[j].last &&
                    runs_[j].first <= runs_[i].last;
        cost(x, a) = blocked ? 1e9 : CostOf(i, static_cast<int>(a), i, static_cast<int>(a));
      }
    }
    const std::vector<int> match = SolveAssignment(cost, 1e8);
    const double before = TotalCost();
    std::vector<int> old(long_runs.size());
    for (size_t x = 0; x < long_runs.size(); ++x) {
      old[x] = runs_[long_runs[x]].label;
      if (match[x] >= 0) runs_[long_runs[x]].label = match[x];
    }
    if (TotalCost() >= before - 1e-6) {
      for (size_t x = 0; x < long_runs.size(); ++x) runs_[long_runs[x]].label = old[x];
      break;
    }
  }
  for (size_t i = 0; i < count_; ++i)
    if (short_label[i] >= 0 && FreeFor(short_label[i], i, i)) runs_[i].label = short_label[i];
}

// Longer runs are visited first: a short piece must not take a name first that a long run fits
// far better (a move is never undone in favour of a run that would have to evict it).
void DistanceRefinement::LocalSearch() {
  std::vector<size_t> by_length(count_);
  for (size_t i = 0; i < count_; ++i) by_length[i] = i;
  std::stable_sort(by_length.begin(), by_length.end(), [&](size_t x, size_t y) {
    return runs_[x].last - runs_[x].first > runs_[y].last - runs_[y].first;
  });
  for (int sweep = 0; sweep < 20; ++sweep) {
    bool improved = false;
    for (size_t i : by_length) {
      for (size_t j = i + 1; j < count_ && runs_[i].label >= 0; ++j) {
        if (runs_[j].label < 0 || runs_[i].label < 0) continue;
        const int li = runs_[i].label, lj = runs_[j].label;
        if (!FreeForExchange(lj, i, j) || !FreeForExchange(li, j, i)) continue;
        const double before = CostOf(i, li, j, lj) + CostOf(j, lj, i, li);
        const double after = CostOf(i, lj, j, li) + CostOf(j, li, i, lj);
        if (after < before - 1e-6) {
          runs_[i].label = lj, runs_[j].label = li;
          improved = true;
        }
      }
      for (int u = 0; u < static_cast<int>(set_.NumMarkers()); ++u) {
        const int li = runs_[i].label;
        if (u == li || !FreeFor(u, i, i)) continue;
        const double now = li >= 0 ? CostOf(i, li, i, li) : UnnamedCost(i);
        if (CostOf(i, u, i, u) < now - 1e-6) {
          runs_[i].label = u;
          improved = true;
        }
      }
    }
    if (!improved) break;
  }
}

std::vector<std::map<int, double>> DistanceRefinement::SegmentFrameVotes() const {
  const size_t columns = in_.NumMarkers();
  std::vector<std::map<int, double>> frame_votes(count_);
  std::vector<Eigen::Vector3d> points;
  std::vector<int> labels_now, votes;
  std::vector<size_t> run_of_point;
  for (size_t f = 0; f < in_.NumFrames() && !anchors_.empty(); ++f) {
    points.clear(), labels_now.clear(), run_of_point.clear();
    for (size_t c = 0; c < columns; ++c) {
      const int64_t r = run_at_[f * columns + c];
      if (r < 0 || runs_[static_cast<size_t>(r)].label < 0) continue;
      points.push_back(in_.At(f, c));
      labels_now.push_back(runs_[static_cast<size_t>(r)].label);
      run_of_point.push_back(static_cast<size_t>(r));
    }
    VoteInSegmentFrames(set_, anchors_, points, labels_now, &votes);
    for (size_t p = 0; p < points.size(); ++p)
      if (votes[p] >= 0) frame_votes[run_of_point[p]][votes[p]] += 1.0;
  }
  return frame_votes;
}

// Inside a segment, where the distances cannot tell its names apart (another subject's cluster has
// other sides), the anchors' frame decides (segment_frames.h): a run whose votes clearly favour
// another name of its segment takes it when the segment's runs so renamed are a permutation of
// their names that is not a turn about the limb and the distances do not object (the total rises
// by less than the ambiguity margin per run). Runs whose names the votes clearly confirm are
// marked in *confirmed.
void DistanceRefinement::RenameBySegmentVotes(const std::vector<std::map<int, double>>& frame_votes,
                                              std::vector<char>* confirmed) {
  for (const SegmentAnchors& a : anchors_) {
    std::vector<size_t> members_runs, changed;
    std::vector<std::pair<int, int>> relabel;  // old -> new
    std::vector<int> new_label(count_, -1);
    for (size_t r = 0; r < count_; ++r)
      if (runs_[r].label >= 0 && set_.SegmentOf(runs_[r].label) == a.segment) members_runs.push_back(r);
    bool consistent = true;
    for (size_t r : members_runs) {
      int best = -1;
      double best_votes = 0.0, total = 0.0;
      for (const auto& [l, v] : frame_votes[r]) {
        total += v;
        if (v > best_votes) best = l, best_votes = v;
      }
      if (total < options_.min_frame_votes || best < 0 || best == runs_[r].label ||
          best_votes < options_.clear_share * total)
        continue;
      changed.push_back(r), new_label[r] = best;
      bool known = false;
      for (const auto& [from, into] : relabel)
        if (from == runs_[r].label) known = true, consistent = consistent && into == best;
      if (!known) relabel.push_back({runs_[r].label, best});
    }
    // A permutation: the new names are the old ones.
    for (const auto& [from, into] : relabel) {
      bool held = false;
      for (const auto& other : relabel) held = held || other.first == into;
      consistent = consistent && held;
    }
    if (!changed.empty() && consistent && !IsTurnAboutLimb(set_, a, relabel)) {
      const double before = TotalCost();
      std::vector<int> old(count_, -1);
      for (size_t r : changed) old[r] = runs_[r].label, runs_[r].label = new_label[r];
      bool clash = false;
      for (size_t r : changed) clash = clash || !FreeFor(runs_[r].label, r, r);
      if (clash || TotalCost() - before > options_.ambiguity_margin * static_cast<double>(changed.size()))
        for (size_t r : changed) runs_[r].label = old[r];
    }
    for (size_t r : members_runs) {
      double total = 0.0, agree = 0.0;
      for (const auto& [l, v] : frame_votes[r]) total += v, agree += l == runs_[r].label ? v : 0.0;
      (*confirmed)[r] = total >= options_.min_frame_votes && agree >= options_.clear_share * total;
    }
  }
}

// Two overlapping runs whose names could be exchanged at almost no cost cannot be told apart (a
// pair of markers whose distances to the rest are alike, placed differently on this subject):
// both lose their names rather than carry a coin toss, unless the anchors' frame confirms both
// and their exchange is not a turn about the limb.
void DistanceRefinement::DropAmbiguous(const std::vector<char>& confirmed) {
  std::vector<int> anchors_of_segment(set_.segments.size(), -1);
  for (size_t k = 0; k < anchors_.size(); ++k)
    anchors_of_segment[static_cast<size_t>(anchors_[k].segment)] = static_cast<int>(k);
  std::vector<char> ambiguous(count_, 0);
  for (size_t i = 0; i < count_; ++i)
    for (size_t j = i + 1; j < count_; ++j) {
      const int li = runs_[i].label, lj = runs_[j].label;
      if (li < 0 || lj < 0 || Pair(i, j).frames < 10) continue;
      if (!FreeForExchange(lj, i, j) || !FreeForExchange(li, j, i)) continue;
      const int segment = set_.SegmentOf(li);
      if (confirmed[i] && confirmed[j] && segment >= 0 && segment == set_.SegmentOf(lj) &&
          anchors_of_segment[static_cast<size_t>(segment)] >= 0 &&
          !IsTurnAboutLimb(set_, anchors_[static_cast<size_t>(anchors_of_segment[static_cast<size_t>(segment)])],
                           {{li, lj}, {lj, li}}))
        continue;
      const double now = CostOf(i, li, j, lj) + CostOf(j, lj, i, li);
      const double exchanged = CostOf(i, lj, j, li) + CostOf(j, li, i, lj);
      if (exchanged - now < options_.ambiguity_margin) ambiguous[i] = ambiguous[j] = 1;
    }
  for (size_t i = 0; i < count_; ++i)
    if (ambiguous[i]) runs_[i].label = -1;
}

// A name whose distances fit worse than leaving the run unnamed is taken back: never a guess.
void DistanceRefinement::DropPoorFits() {
  for (size_t i = 0; i < count_; ++i) {
    if (runs_[i].label < 0) continue;
    double c = 0.0;
    int n = 0;
    for (size_t j = 0; j < count_; ++j)
      if (j != i && runs_[j].label >= 0 && Pair(i, j).frames >= 10 && set_.Distance(runs_[i].label, runs_[j].label) != nullptr)
        c += PairCost(set_, runs_[i].label, runs_[j].label, Pair(i, j), relative_), ++n;
    if (n > 0 && c / n > options_.unnamed_pair_cost) runs_[i].label = -1;
  }
}

}  // namespace mocap

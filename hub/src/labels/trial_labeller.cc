// Labelling a whole recording (see trial_labeller.h).
#include "labels/trial_labeller.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <tuple>

#include "labels/distance_refinement.h"
#include "labels/label_runs.h"
#include "labels/segment_frames.h"
#include "util/assignment.h"

namespace mocap {
namespace {

// This subject's own mean distance of every pair of names over the frames both are named (per
// a * n + b; NaN where fewer than 20 frames): on another subject the frame check below measures
// against these, since its clusters have other sides than the set's (a swap is a departure from
// the subject's own distance, not from another person's).
std::vector<double> OwnDistances(const MarkerTrajectories& in, const MarkerSet& set, const std::vector<Run>& runs,
                                 const std::vector<int64_t>& run_at) {
  const size_t n = set.NumMarkers(), columns = in.NumMarkers();
  std::vector<double> sum(n * n, 0.0);
  std::vector<int> count(n * n, 0);
  std::vector<std::pair<int, size_t>> named;  // (label, column)
  for (size_t f = 0; f < in.NumFrames(); ++f) {
    named.clear();
    for (size_t c = 0; c < columns; ++c) {
      const int64_t r = run_at[f * columns + c];
      if (r >= 0 && runs[static_cast<size_t>(r)].label >= 0) named.push_back({runs[static_cast<size_t>(r)].label, c});
    }
    for (size_t x = 0; x < named.size(); ++x)
      for (size_t y = x + 1; y < named.size(); ++y) {
        const int a = std::min(named[x].first, named[y].first), b = std::max(named[x].first, named[y].first);
        const MarkerDistance* d = set.Distance(a, b);
        if (d == nullptr || d->sd > 5.0 || d->mean > 500.0) continue;  // only the pairs the check uses
        sum[static_cast<size_t>(a) * n + static_cast<size_t>(b)] += (in.At(f, named[x].second) - in.At(f, named[y].second)).norm();
        ++count[static_cast<size_t>(a) * n + static_cast<size_t>(b)];
      }
  }
  std::vector<double> own(n * n, std::nan(""));
  for (size_t i = 0; i < own.size(); ++i)
    if (count[i] >= 20) own[i] = sum[i] / count[i];
  return own;
}

// In one frame, the named points (label per point, -1: none) whose distances to the other named
// points break most of the set's steady pairs lose their names for that frame: a run the tracker
// swapped with another marker is not carried under the wrong name. Steady: an sd of at most 5 mm
// in the set, or 15 mm when the set fits this subject closely (relative <= 2 %: the same person,
// whose looser pairs are still known well). The distance expected is the set's mean, or on
// another subject (relative > 2 %) the subject's own (`own`, OwnDistances) where known. Returns
// how many.
size_t DropBrokenNames(const MarkerSet& set, double relative, const std::vector<double>& own,
                       const std::vector<Eigen::Vector3d>& points, std::vector<int>* labels) {
  const size_t n = set.NumMarkers();
  std::vector<size_t> drop;
  for (size_t p = 0; p < points.size(); ++p) {
    const int a = (*labels)[p];
    if (a < 0) continue;
    int checks = 0, breaks = 0;
    for (size_t q = 0; q < points.size(); ++q) {
      const MarkerDistance* d = q == p || (*labels)[q] < 0 ? nullptr : set.Distance(a, (*labels)[q]);
      if (d == nullptr || d->sd > (relative <= 0.02 ? 15.0 : 5.0) || d->mean > 500.0) continue;
      ++checks;
      double expected = d->mean;
      if (relative > 0.02) {
        const double subject = own[static_cast<size_t>(std::min(a, (*labels)[q])) * n + static_cast<size_t>(std::max(a, (*labels)[q]))];
        if (std::isfinite(subject)) expected = subject;
      }
      breaks += std::abs((points[p] - points[q]).norm() - expected) > 3.0 * d->sd + 5.0 + relative * d->mean;
    }
    if (checks >= 2 && 2 * breaks > checks) drop.push_back(p);
  }
  for (size_t p : drop) (*labels)[p] = -1;
  return drop.size();
}

// In one frame, the named points whose name another point of the frame (named or not) would
// carry far better: the sum over the other named points of each distance's squared departure
// from the set's (in units of the spread PairCost allows, capped at 25 like there) is at least
// `margin` lower with that point in its place. A run the tracker swapped, even one whose
// markers have few steady partners (an arm serving), fits its name worse than the marker it
// swapped with. The names checked are `checked` (per point, -1: none), the partners' `labels`.
// Per point, 1: contested. Frames of more than kMaxContestPoints points are not
// checked (the test grows with the cube of the points).
constexpr size_t kMaxContestPoints = 300;
constexpr double kContestMargin = 20.0;
void ContestedNames(const MarkerSet& set, double relative, const std::vector<Eigen::Vector3d>& points,
                    const std::vector<int>& labels, const std::vector<int>& checked, std::vector<char>* contested) {
  contested->assign(points.size(), 0);
  if (points.size() > kMaxContestPoints) return;
  auto pair_cost = [&](int a, int b, double distance) {
    const MarkerDistance* d = set.Distance(std::min(a, b), std::max(a, b));
    if (d == nullptr || (relative > 0.05 && d->sd > 5.0)) return 0.0;
    const double z = (distance - d->mean) / (d->sd + 3.0 + relative * d->mean);
    return std::min(z * z, 25.0);
  };
  for (size_t p = 0; p < points.size(); ++p) {
    const int a = checked[p];
    if (a < 0) continue;
    double own = 0.0;
    for (size_t q = 0; q < points.size(); ++q)
      if (q != p && labels[q] >= 0) own += pair_cost(a, labels[q], (points[p] - points[q]).norm());
    if (own < kContestMargin) continue;
    for (size_t o = 0; o < points.size() && !(*contested)[p]; ++o) {
      if (o == p) continue;
      double other = 0.0;
      for (size_t q = 0; q < points.size(); ++q)
        if (q != p && q != o && labels[q] >= 0) other += pair_cost(a, labels[q], (points[o] - points[q]).norm());
      (*contested)[p] = other <= own - kContestMargin;
    }
  }
}

// Splits runs where they start or stop breaking their steady distances, or having their name
// contested (ContestedNames), for at least `min_frames` frames (the tracker swapped two markers
// there): the broken part becomes a run of its own without a name, to be named again by the
// refinement. A run the refinement left unnamed is checked with the name its frames supported
// (a run joined from two markers by a swap fits no name as a whole); its pieces that keep
// fitting that name take it back. Once broken, a run stays so until it fits its name again for
// 5 times `min_frames`. Returns whether any was split.
bool SplitBrokenRuns(const MarkerTrajectories& in, const MarkerSet& set, double relative, size_t min_frames,
                     std::vector<Run>* runs, std::vector<int64_t>* run_at) {
  const std::vector<double> own = OwnDistances(in, set, *runs, *run_at);
  const size_t columns = in.NumMarkers();
  std::vector<char> broken(in.points.size(), 0);
  std::vector<Eigen::Vector3d> points;
  std::vector<int> labels, original, checked;
  std::vector<char> contested;
  std::vector<size_t> which;
  for (size_t f = 0; f < in.NumFrames(); ++f) {
    points.clear(), labels.clear(), checked.clear(), which.clear();
    for (size_t c = 0; c < columns; ++c) {
      const int64_t r = (*run_at)[f * columns + c];
      if (r < 0) continue;
      const Run& run = (*runs)[static_cast<size_t>(r)];
      points.push_back(in.At(f, c));
      labels.push_back(run.label);
      checked.push_back(run.label >= 0 ? run.label : run.candidate);
      which.push_back(c);
    }
    original = labels;
    ContestedNames(set, relative, points, original, checked, &contested);
    DropBrokenNames(set, relative, own, points, &labels);
    for (size_t i = 0; i < which.size(); ++i)
      broken[f * columns + which[i]] = checked[i] >= 0 && ((original[i] >= 0 && labels[i] < 0) || contested[i]);
  }
  bool split = false;
  const size_t count = runs->size();
  for (size_t r = 0; r < count; ++r) {
    const int label = (*runs)[r].label >= 0 ? (*runs)[r].label : (*runs)[r].candidate;
    if (label < 0) continue;
    const size_t column = (*runs)[r].column;
    // Pieces of equal state; short flickers join their neighbours.
    std::vector<std::pair<size_t, size_t>> pieces;  // [first, last]
    std::vector<char> state;
    for (size_t f = (*runs)[r].first; f <= (*runs)[r].last; ++f) {
      const char b = broken[f * columns + column];
      if (!state.empty() && state.back() == b) {
        pieces.back().second = f;
      } else {
        pieces.push_back({f, f});
        state.push_back(b);
      }
    }
    for (size_t i = 0; i < pieces.size(); ++i)
      if (pieces[i].second - pieces[i].first + 1 < min_frames && pieces.size() > 1) state[i] = i > 0 ? state[i - 1] : 0;
    auto merge = [](const std::vector<std::pair<size_t, size_t>>& in_pieces, const std::vector<char>& in_state,
                    std::vector<std::pair<size_t, size_t>>* out_pieces, std::vector<char>* out_state) {
      out_pieces->clear(), out_state->clear();
      for (size_t i = 0; i < in_pieces.size(); ++i) {
        if (!out_pieces->empty() && out_state->back() == in_state[i]) out_pieces->back().second = in_pieces[i].second;
        else out_pieces->push_back(in_pieces[i]), out_state->push_back(in_state[i]);
      }
    };
    std::vector<std::pair<size_t, size_t>> merged;
    std::vector<char> merged_state;
    merge(pieces, state, &merged, &merged_state);
    // Once broken, a run stays so until it fits its name again for a while (5 times min_frames):
    // a swapped marker fits the name now and then as the limb moves (every such stretch would
    // otherwise become a piece of its own, and the pieces block each other's renaming).
    for (size_t i = 1; i < merged.size(); ++i)
      if (!merged_state[i] && merged_state[i - 1] && merged[i].second - merged[i].first + 1 < 5 * min_frames)
        merged_state[i] = 1;
    pieces = merged, state = merged_state;
    merge(pieces, state, &merged, &merged_state);
    if (merged.size() < 2) continue;
    split = true;
    for (size_t i = 0; i < merged.size(); ++i) {
      size_t target = r;
      if (i == 0) {
        (*runs)[r].last = merged[0].second;
        (*runs)[r].label = (*runs)[r].candidate = merged_state[0] ? -1 : label;
      } else {
        target = runs->size();
        Run piece;
        piece.column = column;
        piece.first = merged[i].first, piece.last = merged[i].second;
        piece.label = piece.candidate = merged_state[i] ? -1 : label;
        if (piece.label >= 0) piece.support[label] = 1.0, piece.total = 1.0;
        runs->push_back(piece);
      }
      for (size_t f = merged[i].first; f <= merged[i].second; ++f)
        if ((*run_at)[f * columns + column] >= 0) (*run_at)[f * columns + column] = static_cast<int64_t>(target);
    }
  }
  return split;
}

}  // namespace

namespace {

using TakenFrames = std::vector<std::vector<std::pair<size_t, size_t>>>;  // per name: (first, last) of its runs

// The frame-by-frame pass: each column's unbroken runs (a run ends where the column has no point
// or the live labeller revoked its name) and the names the labeller gave or proposed, as votes.
void VoteFrameByFrame(const MarkerTrajectories& in, MarkerLabeller* labeller, std::vector<Run>* runs,
                      std::vector<int64_t>* run_at) {
  const size_t columns = in.NumMarkers();
  std::vector<int64_t> run_of_column(columns, -1);
  std::vector<Eigen::Vector3d> points;
  std::vector<int64_t> tracks;
  std::vector<char> broken(columns, 0);
  for (size_t f = 0; f < in.NumFrames(); ++f) {
    points.clear(), tracks.clear();
    for (size_t c = 0; c < columns; ++c) {
      if (!in.Has(f, c)) {
        run_of_column[c] = -1;
        continue;
      }
      if (run_of_column[c] < 0 || broken[c]) {
        run_of_column[c] = static_cast<int64_t>(runs->size());
        runs->push_back(Run{c, f, f, {}, 0.0, -1, -1});
        broken[c] = 0;
      }
      (*runs)[static_cast<size_t>(run_of_column[c])].last = f;
      (*run_at)[f * columns + c] = run_of_column[c];
      points.push_back(in.At(f, c));
      tracks.push_back(run_of_column[c]);
    }
    const std::vector<int>& labels = labeller->Update(points, tracks);
    const std::vector<int>& proposals = labeller->proposals();
    for (size_t p = 0; p < points.size(); ++p) {
      Run& run = (*runs)[static_cast<size_t>(tracks[p])];
      // A frame holding a name counts twice a vote: it passed the swap guard.
      if (labels[p] >= 0) run.support[labels[p]] += 2.0, run.total += 2.0;
      if (proposals[p] >= 0) run.support[proposals[p]] += 1.0, run.total += 1.0;
      if (labels[p] < 0 && proposals[p] < 0) run.total += 1.0;
    }
    for (int64_t track : labeller->revoked()) broken[(*runs)[static_cast<size_t>(track)].column] = 1;
  }
}

// One name per run: the best supported first, never two overlapping runs with one name.
void NameRunsBySupport(std::vector<Run>* runs, TakenFrames* taken) {
  std::vector<std::tuple<double, size_t, int>> candidates;  // (support, run, label)
  for (size_t r = 0; r < runs->size(); ++r)
    for (const auto& [label, support] : (*runs)[r].support)
      if (2.0 * support >= (*runs)[r].total) candidates.emplace_back(support, r, label);
  std::sort(candidates.begin(), candidates.end(), [](const auto& x, const auto& y) { return std::get<0>(x) > std::get<0>(y); });
  for (const auto& [support, r, label] : candidates) {
    Run& run = (*runs)[r];
    if (run.label >= 0) continue;
    bool overlaps = false;
    for (const auto& [first, last] : (*taken)[static_cast<size_t>(label)])
      overlaps = overlaps || (run.first <= last && first <= run.last);
    if (overlaps) continue;
    run.label = run.candidate = label;
    (*taken)[static_cast<size_t>(label)].push_back({run.first, run.last});
  }
}

// The named recording: the names placed, in the set's order, then the input columns left with
// data; each frame's names checked against the distances (names that break them, or that two
// runs hold at their ends, are dropped in that frame).
void WriteNamed(const MarkerTrajectories& in, const MarkerSet& set, const std::vector<Run>& runs,
                const std::vector<int64_t>& run_at, const TakenFrames& taken, double relative, TrialLabelling* out) {
  const size_t columns = in.NumMarkers();
  std::vector<int> column_of_label(set.NumMarkers(), -1);
  MarkerTrajectories& named = out->named;
  named.rate_hz = in.rate_hz;
  for (size_t a = 0; a < set.NumMarkers(); ++a)
    if (!taken[a].empty()) {
      column_of_label[a] = static_cast<int>(named.names.size());
      named.names.push_back(set.names[a]);
    }
  out->names_placed = named.names.size();
  const std::vector<double> own = OwnDistances(in, set, runs, run_at);
  // Per frame and input column the name its point carries (-1: none), after the frame check.
  std::vector<int> label_at(in.points.size(), -1);
  std::vector<int> leftover_column(columns, -1);
  std::vector<Eigen::Vector3d> frame_points;
  std::vector<int> frame_labels;
  std::vector<size_t> frame_columns;
  std::vector<int> holders(set.NumMarkers(), 0);  // per name: the points holding it in a frame
  for (size_t f = 0; f < in.NumFrames(); ++f) {
    frame_points.clear(), frame_labels.clear(), frame_columns.clear();
    for (size_t c = 0; c < columns; ++c) {
      const int64_t r = run_at[f * columns + c];
      if (r < 0) continue;
      frame_points.push_back(in.At(f, c));
      frame_labels.push_back(runs[static_cast<size_t>(r)].label);
      frame_columns.push_back(c);
    }
    out->frame_names_dropped += DropBrokenNames(set, relative, own, frame_points, &frame_labels);
    for (int label : frame_labels)
      if (label >= 0) ++holders[static_cast<size_t>(label)];
    for (int& label : frame_labels)
      if (label >= 0 && holders[static_cast<size_t>(label)] > 1) ++out->frame_names_dropped, label = -1;
    std::fill(holders.begin(), holders.end(), 0);
    for (size_t i = 0; i < frame_columns.size(); ++i) {
      label_at[f * columns + frame_columns[i]] = frame_labels[i];
      if (frame_labels[i] < 0) leftover_column[frame_columns[i]] = 0;
    }
  }
  for (size_t c = 0; c < columns; ++c)
    if (leftover_column[c] == 0) {
      leftover_column[c] = static_cast<int>(named.names.size());
      named.names.push_back(in.names[c]);
    }
  for (size_t f = 0; f < in.NumFrames(); ++f) {
    const size_t row = named.AddFrame(in.frame_numbers[f]);
    for (size_t c = 0; c < columns; ++c) {
      if (run_at[f * columns + c] < 0) continue;
      const int label = label_at[f * columns + c];
      const int column = label >= 0 ? column_of_label[static_cast<size_t>(label)] : leftover_column[c];
      named.At(row, static_cast<size_t>(column)) = in.At(f, c);
      ++out->points;
      out->named_points += label >= 0;
    }
  }
}

}  // namespace

TrialLabelling LabelTrajectories(const MarkerTrajectories& in, const MarkerSet& set, const LabellerOptions& options) {
  MarkerLabeller labeller(set, options);
  std::vector<Run> runs;
  std::vector<int64_t> run_at(in.points.size(), -1);  // per (frame, column)
  VoteFrameByFrame(in, &labeller, &runs, &run_at);
  TakenFrames taken(set.NumMarkers());
  NameRunsBySupport(&runs, &taken);
  const std::vector<SegmentAnchors> anchors = ChooseSegmentAnchors(set);
  double relative = DistanceRefinement(in, set, anchors, run_at, &runs).Refine(&taken);
  // Runs the tracker swapped mid-way: split where they break their distances, then named again.
  if (SplitBrokenRuns(in, set, relative, 5, &runs, &run_at))
    relative = DistanceRefinement(in, set, anchors, run_at, &runs).Refine(&taken);
  TrialLabelling out;
  out.runs = runs.size();
  out.named_runs = static_cast<size_t>(std::count_if(runs.begin(), runs.end(), [](const Run& r) { return r.label >= 0; }));
  WriteNamed(in, set, runs, run_at, taken, relative, &out);
  out.stats = labeller.stats();
  return out;
}

}  // namespace mocap

// Trades between close markers judged by the smoothness of both trajectories around them.
#include "track/hindsight_swaps.h"

#include <algorithm>
#include <numeric>
#include <utility>

#include "util/assignment.h"
#include "util/join_roughness.h"

namespace mocap {

HindsightSwaps::HindsightSwaps(const HindsightSwapOptions& options, Sink sink)
    : options_((options.Check(), options)),
      sink_(std::move(sink)),
      distances_(options.pair_radius_mm, options.rigid_max_sd_mm, options.rigid_tolerance_mm) {}

namespace {

// Sum of squared second differences of the trajectory through window rows [first, N) whose
// positions come from `a` except where `from_b` says b's.
template <int N>
double Roughness(const Eigen::Vector3d (&a)[N], const Eigen::Vector3d (&b)[N], const bool (&from_b)[N], int first) {
  double sum = 0.0;
  for (int k = first + 1; k + 1 < N; ++k) {
    const Eigen::Vector3d& before = from_b[k - 1] ? b[k - 1] : a[k - 1];
    const Eigen::Vector3d& here = from_b[k] ? b[k] : a[k];
    const Eigen::Vector3d& after = from_b[k + 1] ? b[k + 1] : a[k + 1];
    sum += SquaredSecondDifference(before, here, after);
  }
  return sum;
}

}  // namespace

template <class PositionAt>
double HindsightSwaps::RigidExcess(size_t i, int from, int to, int skip, PositionAt position_at,
                                   const std::vector<int>* takes) const {
  const int num_columns = static_cast<int>(present_.size());
  double sum = 0.0;
  for (const SteadyDistances::Neighbour& neighbour : neighbours_[i]) {
    if (neighbour.column == skip || neighbour.column >= num_columns) continue;
    // The neighbour's own rows, or those of the column it takes.
    const int taken = takes != nullptr ? (*takes)[neighbour.column] : -1;
    const int source = taken >= 0 ? columns_[taken].label : neighbour.column;
    for (int k = from; k < to; ++k) {
      const Eigen::Vector3d* position = position_at(k);
      if (position == nullptr || !(present_[source] >> k & 1)) continue;
      const Eigen::Vector3d& other =
          taken >= 0 ? columns_[taken].positions[k] : window_[static_cast<size_t>(k) * num_columns + source];
      sum += SteadyDistances::Excess(neighbour, (*position - other).norm());
    }
  }
  return options_.rigid_weight * sum;
}

void HindsightSwaps::Relabel(size_t from_row, size_t to_row, const std::vector<int>& label_of_column) {
  for (size_t r = from_row; r < to_row; ++r) {
    for (TrackSample& sample : rows_[r].samples) sample.marker = label_of_column[sample.marker];
  }
}

void HindsightSwaps::RelabelForGood(size_t from_row, const std::vector<int>& label_of_column) {
  Relabel(from_row, rows_.size(), label_of_column);
  for (int& column : column_of_marker_) {
    if (column >= 0) column = label_of_column[column];  // not kNoColumn, kColumnGivenAway
  }
  const std::vector<uint64_t> last_frame = last_frame_of_column_;
  const std::vector<Eigen::Vector3d> last_position = last_position_of_column_;
  for (size_t column = 0; column < label_of_column.size(); ++column) {
    last_frame_of_column_[label_of_column[column]] = last_frame[column];
    last_position_of_column_[label_of_column[column]] = last_position[column];
  }
}

// The window holds rows t-kBefore ... t+kAfter (at the start of the data only t-1 on: `before`
// is 1). Two judgements, each undoing what removes most of the roughness (second differences)
// of the trajectories involved:
// 1. short trades: each pair of close markers present in every row, traded back for frames
//    [t, t+1) or [t, t+2);
// 2. trades for good: the markers that jump across the boundary and their neighbours, each
//    one's past (rows before t) joined to the future (rows from t) that continues it most
//    smoothly, an optimal assignment (chains of three or more markers included).
void HindsightSwaps::JudgeBoundary(size_t t, int before) {
  const int first = kBefore - before;  // window index of the first row held
  if (!GatherColumns(t, first)) return;
  MarkJumpsAndBends(first, before);
  UndoShortTrades(t, first);
  TradeForGood(t, before);
}

bool HindsightSwaps::GatherColumns(size_t t, int first) {
  // Every sample's column is one of the columns issued so far.
  const int num_columns = static_cast<int>(last_frame_of_column_.size());
  // present_[column]: one bit per window row holding a sample of the column.
  present_.assign(num_columns, 0);
  if (window_.size() < static_cast<size_t>(kHeldRows) * num_columns) window_.resize(static_cast<size_t>(kHeldRows) * num_columns);
  for (int k = first; k < kHeldRows; ++k) {
    for (const TrackSample& sample : rows_[t - kBefore + k].samples) {
      present_[sample.marker] |= 1 << k;
      window_[static_cast<size_t>(k) * num_columns + sample.marker] = sample.position;
    }
  }
  // Joinable columns: present from the first row to t+1 (both second differences at the boundary).
  const int joinable_mask = ((1 << (kBefore + 2)) - 1) & ~((1 << first) - 1);
  const int full_mask = ((1 << kHeldRows) - 1) & ~((1 << first) - 1);
  columns_.clear();
  for (int column = 0; column < num_columns; ++column) {
    if ((present_[column] & joinable_mask) != joinable_mask) continue;
    columns_.emplace_back();
    Column& judged = columns_.back();
    judged.label = column;
    judged.full = (present_[column] & full_mask) == full_mask;
    for (int k = first; k < kHeldRows; ++k) {
      if (present_[column] >> k & 1) judged.positions[k] = window_[static_cast<size_t>(k) * num_columns + column];
    }
  }
  return columns_.size() >= 2;
}

void HindsightSwaps::MarkJumpsAndBends(int first, int before) {
  // Only a column that jumps here can be part of a trade: its second differences at t-1 and t.
  const double min_jump2 = options_.min_jump_mm * options_.min_jump_mm;
  neighbours_.resize(columns_.size());
  for (size_t i = 0; i < columns_.size(); ++i) {
    Column& column = columns_[i];
    const Eigen::Vector3d* p = column.positions;
    double jump = SquaredSecondDifference(p[kBefore - 1], p[kBefore], p[kBefore + 1]);
    if (before == 2) jump = std::max(jump, SquaredSecondDifference(p[kBefore - 2], p[kBefore - 1], p[kBefore]));
    column.jumps = jump >= 0.25 * min_jump2;
    distances_.SteadyNeighbours(column.label, &neighbours_[i]);
    if (neighbours_[i].empty()) continue;
    const double after = RigidExcess(i, kBefore, kHeldRows, -1, Own(column));
    // Bent: by 2 mm beyond the tolerance over the four rows from the boundary (or 4 mm in one).
    column.bends = after > 0.0 && after >= options_.rigid_weight * kBentExcess &&
                   RigidExcess(i, first, kBefore, -1, Own(column)) <= 0.25 * after;
  }
}

bool HindsightSwaps::Close(const Column& a, const Column& b) const {
  return (a.positions[kBefore - 1] - b.positions[kBefore - 1]).squaredNorm() <=
         options_.pair_radius_mm * options_.pair_radius_mm;
}

void HindsightSwaps::UndoShortTrades(size_t t, int first) {
  std::vector<int> label(last_frame_of_column_.size());
  ShortTrade best;
  while (BestShortTrade(first, &best)) {
    std::iota(label.begin(), label.end(), 0);
    std::swap(label[columns_[best.i].label], label[columns_[best.j].label]);
    Relabel(t, t + best.frames, label);
    ++swaps_undone_;
    columns_[best.i].used = columns_[best.j].used = true;
    // The rows changed under the other columns' positions only for these two; both are done.
  }
}

bool HindsightSwaps::BestShortTrade(int first, ShortTrade* best) const {
  const double min_jump2 = options_.min_jump_mm * options_.min_jump_mm;
  *best = ShortTrade{};
  for (size_t i = 0; i < columns_.size(); ++i) {
    const Column& a = columns_[i];
    if (!(a.jumps || a.bends) || !a.full || a.used) continue;
    for (size_t j = 0; j < columns_.size(); ++j) {
      const Column& b = columns_[j];
      if (j == i || !b.full || b.used || ((b.jumps || b.bends) && j < i) || !Close(a, b)) continue;
      bool as_is[kHeldRows] = {};
      const double roughness_now = Roughness(a.positions, b.positions, as_is, first) +
                                   Roughness(b.positions, a.positions, as_is, first);
      for (int frames = 1; frames <= 2; ++frames) {
        bool traded[kHeldRows] = {};
        for (int k = kBefore; k < kBefore + frames; ++k) traded[k] = true;
        // Both columns' distances from the boundary on, as they are and traded: a trade back
        // that leaves the later rows bent is no repair (a trade for good may be).
        const auto traded_a = [&](int k) { return k < kBefore + frames ? Own(b)(k) : Own(a)(k); };
        const auto traded_b = [&](int k) { return k < kBefore + frames ? Own(a)(k) : Own(b)(k); };
        const double now = roughness_now + RigidExcess(i, kBefore, kHeldRows, b.label, Own(a)) +
                           RigidExcess(j, kBefore, kHeldRows, a.label, Own(b));
        const double then = Roughness(a.positions, b.positions, traded, first) +
                            Roughness(b.positions, a.positions, traded, first) +
                            RigidExcess(i, kBefore, kHeldRows, b.label, traded_a) +
                            RigidExcess(j, kBefore, kHeldRows, a.label, traded_b);
        const double gain = now - then;
        if (then <= options_.improvement * now && gain >= min_jump2 && gain > best->gain) {
          *best = ShortTrade{i, j, frames, gain};
        }
      }
    }
  }
  return best->frames > 0;
}

double HindsightSwaps::JoinCost(const Column& past, const Column& future, int before) const {
  const Eigen::Vector3d* p = past.positions;
  const Eigen::Vector3d* f = future.positions;
  if (before == 1) return SquaredSecondDifference(p[kBefore - 1], f[kBefore], f[kBefore + 1]);
  return JoinRoughness(p[kBefore - 2], p[kBefore - 1], f[kBefore], f[kBefore + 1]);
}

void HindsightSwaps::TradeForGood(size_t t, int before) {
  // The group is every jumping column and the columns close to one.
  group_.clear();
  for (size_t i = 0; i < columns_.size(); ++i) {
    if (columns_[i].used) continue;
    bool take = columns_[i].jumps || columns_[i].bends;
    for (size_t j = 0; j < columns_.size() && !take; ++j) {
      take = (columns_[j].jumps || columns_[j].bends) && !columns_[j].used && Close(columns_[i], columns_[j]);
    }
    if (take) group_.push_back(static_cast<int>(i));
  }
  if (group_.size() < 2) return;
  // Each entry's distances are judged as if the two traded (exact for pairs; a cycle of three or
  // more is judged whole below).
  const size_t n = group_.size();
  Eigen::MatrixXd cost(n, n);
  takes_.assign(last_frame_of_column_.size(), -1);
  for (size_t r = 0; r < n; ++r) {
    const Column& past = columns_[group_[r]];
    for (size_t c = 0; c < n; ++c) {
      const Column& future = columns_[group_[c]];
      if (r != c && !Close(past, future)) {
        cost(r, c) = kForbidden;
        continue;
      }
      if (r != c) takes_[future.label] = group_[r];
      cost(r, c) = JoinCost(past, future, before) + RigidExcess(group_[r], kBefore, kHeldRows, -1, Own(future), &takes_);
      takes_[future.label] = -1;
    }
  }
  item_labels_.clear();
  for (int i : group_) item_labels_.push_back(columns_[i].label);
  // The solver saw each future's distances to its neighbours as they are; a cycle is judged by
  // the distances with all its members traded (clusters of three trading all round).
  const auto judge = [&](const std::vector<size_t>& cycle, const std::vector<int>& chosen, double* as_is,
                         double* then) {
    *as_is = *then = 0.0;
    for (size_t k : cycle) {
      *as_is += cost(k, k);  // exact: every neighbour in its own rows
      takes_[columns_[group_[k]].label] = group_[chosen[k]];
    }
    for (size_t k : cycle) {
      const Column& future = columns_[group_[chosen[k]]];
      *then += JoinCost(columns_[group_[k]], future, before) +
               RigidExcess(group_[k], kBefore, kHeldRows, -1, Own(future), &takes_);
    }
    for (size_t k : cycle) takes_[columns_[group_[k]].label] = -1;
  };
  std::vector<int> label(last_frame_of_column_.size());
  std::iota(label.begin(), label.end(), 0);
  if (AcceptCycles(cost, &label, judge) > 0) RelabelForGood(t, label);
}

int HindsightSwaps::AcceptCycles(const Eigen::MatrixXd& cost, std::vector<int>* label, const CycleJudge& judge) {
  const std::vector<int> chosen = SolveAssignment(cost, 0.5 * kForbidden);
  // Every item is assigned: the identity is always allowed and the solver takes the most pairs.
  if (std::find(chosen.begin(), chosen.end(), -1) != chosen.end()) return 0;
  const size_t n = chosen.size();
  const double min_jump2 = options_.min_jump_mm * options_.min_jump_mm;
  int accepted = 0;
  std::vector<char> seen(n, 0);
  for (size_t r = 0; r < n; ++r) {
    if (seen[r] || chosen[r] == static_cast<int>(r)) continue;
    double as_is = 0.0, then = 0.0;
    cycle_.clear();
    size_t k = r;
    do {
      seen[k] = 1;
      cycle_.push_back(k);
      as_is += cost(k, k);
      then += cost(k, chosen[k]);
      k = static_cast<size_t>(chosen[k]);
    } while (k != r);
    if (judge) judge(cycle_, chosen, &as_is, &then);
    if (then > options_.improvement * as_is || as_is - then < min_jump2) continue;
    k = r;
    do {
      (*label)[item_labels_[chosen[k]]] = item_labels_[k];
      k = static_cast<size_t>(chosen[k]);
    } while (k != r);
    ++accepted;
  }
  swaps_undone_ += accepted;
  return accepted;
}

void HindsightSwaps::Emit(size_t rows) {
  for (size_t r = 0; r < rows && !rows_.empty(); ++r) {
    if (options_.enabled) distances_.Learn(rows_.front().frame_number, rows_.front().samples);
    sink_(rows_.front().frame_number, rows_.front().samples);
    last_sent_ = rows_.front().frame_number;
    sent_any_ = true;
    rows_.pop_front();
  }
}

int HindsightSwaps::IssueColumn() {
  last_frame_of_column_.push_back(kNever);
  last_position_of_column_.emplace_back(Eigen::Vector3d::Zero());
  return static_cast<int>(last_frame_of_column_.size()) - 1;
}

void HindsightSwaps::Place(int column, TrackSample sample) {
  if (last_frame_of_column_[column] == kNever || sample.frame_number > last_frame_of_column_[column]) {
    last_frame_of_column_[column] = sample.frame_number;
    last_position_of_column_[column] = sample.position;
  }
  sample.marker = column;
  if (sample.frame_number < rows_.front().frame_number || sample.frame_number > rows_.back().frame_number) {
    late_.push_back(sample);
  } else {
    rows_[sample.frame_number - rows_.front().frame_number].samples.push_back(sample);
  }
}

// A new marker continues a column lost at most kJoinFrames before its first sample, within
// pair_radius_mm of where it was last, when its samples in the held rows keep that column's
// steady distances to at least two neighbours (all within tolerance): a cluster's marker found
// again, as a new track of the tracker after a jump it could not follow. The column that fits
// best is taken; otherwise a new one is issued.
int HindsightSwaps::ColumnForNewMarker(int marker, const std::vector<TrackSample>& samples) {
  if (options_.rigid_weight <= 0.0 || rows_.empty()) return IssueColumn();
  uint64_t first_frame = 0;
  const TrackSample* first = nullptr;
  for (const TrackSample& sample : samples) {
    if (sample.marker == marker && (first == nullptr || sample.frame_number < first_frame)) {
      first = &sample;
      first_frame = sample.frame_number;
    }
  }
  const auto row_of = [&](uint64_t frame) -> const Row* {
    if (frame < rows_.front().frame_number || frame > rows_.back().frame_number) return nullptr;
    return &rows_[frame - rows_.front().frame_number];
  };
  int best = -1;
  double best_deviation = 0.0;
  std::vector<SteadyDistances::Neighbour> neighbours;
  for (int column = 0; column < static_cast<int>(last_frame_of_column_.size()); ++column) {
    const uint64_t last = last_frame_of_column_[column];
    if (last == kNever || last >= first_frame || first_frame - last > kJoinFrames) continue;
    if ((first->position - last_position_of_column_[column]).norm() > options_.pair_radius_mm) continue;
    distances_.SteadyNeighbours(column, &neighbours);
    std::vector<char> neighbour_seen(neighbours.size(), 0);
    double deviation = 0.0;
    int checks = 0;
    bool fits = true;
    for (const TrackSample& sample : samples) {
      if (sample.marker != marker || !fits) continue;
      const Row* row = row_of(sample.frame_number);
      if (row == nullptr) continue;
      for (size_t k = 0; k < neighbours.size() && fits; ++k) {
        for (const TrackSample& other : row->samples) {
          if (other.marker != neighbours[k].column) continue;
          const double distance = (sample.position - other.position).norm();
          fits = SteadyDistances::Excess(neighbours[k], distance) == 0.0;
          deviation += std::abs(distance - neighbours[k].mean_mm);
          ++checks;
          neighbour_seen[k] = 1;
          break;
        }
      }
    }
    const int distinct = static_cast<int>(std::count(neighbour_seen.begin(), neighbour_seen.end(), 1));
    if (!fits || distinct < 2) continue;
    deviation /= checks;
    if (best < 0 || deviation < best_deviation) {
      best = column;
      best_deviation = deviation;
    }
  }
  if (best < 0) return IssueColumn();
  ++columns_joined_;
  // The marker that held the column, if the tracker finds it again, takes a column of its own.
  for (int& column : column_of_marker_) {
    if (column == best) column = kColumnGivenAway;
  }
  return best;
}

void HindsightSwaps::Add(uint64_t frame_number, const std::vector<TrackSample>& samples) {
  if (!options_.enabled) {
    sink_(frame_number, samples);
    return;
  }
  // A pause (frames without output) ends the judged stretch: the held rows go out.
  if (!rows_.empty() && frame_number > rows_.back().frame_number + 1) Finish();
  if (rows_.empty() || frame_number > rows_.back().frame_number) rows_.push_back({frame_number, {}});
  late_.clear();
  // Samples of markers with a column first, then new markers: a column of their own or that of a
  // marker lost just before whose cluster they fit (ColumnForNewMarker, which looks at the rows).
  for (const TrackSample& sample : samples) {
    if (sample.marker >= static_cast<int>(column_of_marker_.size())) {
      column_of_marker_.resize(sample.marker + 1, kNoColumn);
    }
  }
  new_markers_.clear();
  for (const TrackSample& sample : samples) {
    int& column = column_of_marker_[sample.marker];
    if (column == kNoColumn) {
      new_markers_.push_back(sample.marker);
      continue;
    }
    if (column == kColumnGivenAway) column = IssueColumn();  // found again after its column went on
    Place(column, sample);
  }
  // In the tracker's order: without joins every marker's column is its own number.
  std::sort(new_markers_.begin(), new_markers_.end());
  new_markers_.erase(std::unique(new_markers_.begin(), new_markers_.end()), new_markers_.end());
  for (int marker : new_markers_) column_of_marker_[marker] = ColumnForNewMarker(marker, samples);
  for (const TrackSample& sample : samples) {
    if (std::binary_search(new_markers_.begin(), new_markers_.end(), sample.marker)) {
      Place(column_of_marker_[sample.marker], sample);
    }
  }
  if (!late_.empty()) sink_(sent_any_ ? last_sent_ : frame_number, late_);
  if (!started_) {
    if (rows_.size() >= kStartRows) JudgeStart();
    return;
  }
  if (rows_.size() == kHeldRows) JudgeBoundary(kBefore, kBefore);
  if (rows_.size() >= kHeldRows) Emit(rows_.size() - kHeldRows + 1);
}

void HindsightSwaps::JudgeStart() {
  started_ = true;
  if (rows_.size() < kBefore + kAfter) return;
  LabelStartBackward();
  for (size_t t = 1; t + kAfter < rows_.size(); ++t) JudgeBoundary(t, t == 1 ? 1 : kBefore);
  if (rows_.size() >= kHeldRows) Emit(rows_.size() - kHeldRows + 1);
}

void HindsightSwaps::Finish() {
  if (!started_) JudgeStart();
  Emit(rows_.size());
  started_ = false;  // what comes next (after a pause) starts again
}

void HindsightSwaps::LabelStartBackward() {
  // index[k][column]: the column's sample in rows_[t + k].samples (-1: none), rows t, t+1, t+2.
  const auto index_row = [&](const Row& row, std::vector<int>* index) {
    index->assign(last_frame_of_column_.size(), -1);
    for (size_t i = 0; i < row.samples.size(); ++i) (*index)[row.samples[i].marker] = static_cast<int>(i);
  };
  const double radius2 = options_.pair_radius_mm * options_.pair_radius_mm;
  std::vector<int> index[3];
  std::vector<int> label(last_frame_of_column_.size());
  std::vector<Eigen::Vector3d> predicted, measured;
  std::vector<char> has_prediction, has_sample;
  for (size_t t = rows_.size() - 2; t-- > 0;) {
    for (int k = 0; k < 3; ++k) index_row(rows_[t + k], &index[k]);
    // Items: columns with a sample in row t or a prediction (samples in rows t+1 and t+2).
    item_labels_.clear();
    predicted.clear();
    measured.clear();
    has_prediction.clear();
    has_sample.clear();
    for (size_t c = 0; c < last_frame_of_column_.size(); ++c) {
      const bool prediction = index[1][c] >= 0 && index[2][c] >= 0;
      const bool sample = index[0][c] >= 0;
      if (!prediction && !sample) continue;
      item_labels_.push_back(static_cast<int>(c));
      has_prediction.push_back(prediction);
      has_sample.push_back(sample);
      predicted.push_back(prediction ? Eigen::Vector3d(2.0 * rows_[t + 1].samples[index[1][c]].position -
                                                       rows_[t + 2].samples[index[2][c]].position)
                                     : Eigen::Vector3d::Zero());
      measured.push_back(sample ? rows_[t].samples[index[0][c]].position : Eigen::Vector3d::Zero());
    }
    const size_t n = item_labels_.size();
    if (n < 2) continue;
    // cost(r, c): item r receives item c's row-t sample (or nothing). A column predicted back
    // pays the squared distance from its prediction to the sample (forbidden beyond the pair
    // radius, but for its own) and nothing for receiving nothing; a column not predicted pays
    // `unexplained` for holding a sample, nothing for holding none. As many items receive
    // nothing whatever the assignment: a sample is only left to a column not predicted where no
    // predicted column is near it. The identity is the rows as tracked.
    const double unexplained = radius2;
    Eigen::MatrixXd cost(n, n);
    for (size_t r = 0; r < n; ++r) {
      for (size_t c = 0; c < n; ++c) {
        if (!has_prediction[r]) {
          cost(r, c) = has_sample[c] ? unexplained : 0.0;
        } else if (!has_sample[c]) {
          cost(r, c) = 0.0;
        } else {
          const double d2 = (measured[c] - predicted[r]).squaredNorm();
          cost(r, c) = r == c || d2 <= radius2 ? d2 : kForbidden;
        }
      }
    }
    std::iota(label.begin(), label.end(), 0);
    if (AcceptCycles(cost, &label) > 0) Relabel(t, t + 1, label);
  }
}

}  // namespace mocap

// Identity swaps undone with hindsight, a few frames after the fact (offline output only). Two
// close markers whose tracks traded points show it in both trajectories: each jumps by the
// distance between the markers where the trade starts (and again where it ends), an acceleration
// no limb makes between two frames. With the frames after a trade in hand the choice is easy:
// for each pair of close markers, the trade that makes both trajectories smoothest (none, the
// pair traded for one or two frames, or for good from here on) is undone when it removes most of
// their acceleration. Rigid clusters weigh more than smoothness: the distances each column kept
// to its close neighbours (track/steady_distances.h, learned from the rows emitted) must hold in
// the judged rows, so a labelling that bends a cluster is traded even where it is smooth, and one
// that keeps it is kept even where a marker seems to jump. Rows are held back `kHeldRows` frames;
// memory is bounded by them and by the pairs of columns that came close.
// Single-threaded; never throws on data.
#pragma once

#include <cstdint>
#include <deque>
#include <functional>
#include <vector>

#include "track/steady_distances.h"
#include "track/track_options.h"
#include "track/tracker.h"

namespace mocap {

class HindsightSwaps {
 public:
  // Receives frame numbers in order with their samples, and late samples (a newly confirmed
  // track's earlier frames) under the last frame number sent, as the tracker gives them.
  using Sink = std::function<void(uint64_t frame_number, const std::vector<TrackSample>& row)>;

  // Checks the options (std::invalid_argument).
  HindsightSwaps(const HindsightSwapOptions& options, Sink sink);

  // The tracker's samples after frame `frame_number` was processed (Tracker::Update's output).
  void Add(uint64_t frame_number, const std::vector<TrackSample>& samples);
  // Emits every row still held.
  void Finish();

  long long swaps_undone() const { return swaps_undone_; }
  // New markers of the tracker that continue a lost column (its cluster's distances fit).
  long long columns_joined() const { return columns_joined_; }
  // Output columns issued (when enabled; otherwise the tracker's markers pass through).
  int num_columns() const { return static_cast<int>(last_frame_of_column_.size()); }

 private:
  struct Row {
    uint64_t frame_number = 0;
    std::vector<TrackSample> samples;
  };
  // The boundary between rows [t-1] and [t] is judged with rows t-2 ... t+3.
  static constexpr int kBefore = 2;
  static constexpr int kAfter = 3;
  static constexpr int kHeldRows = kBefore + kAfter + 1;
  struct Column {
    int label = 0;
    bool full = false;   // present in every row of the window
    bool jumps = false;  // accelerates across the boundary by more than noise does
    bool bends = false;  // keeps its steady distances before the boundary and not after it
    bool used = false;   // already part of a trade undone at this boundary
    Eigen::Vector3d positions[kHeldRows];  // by window row (row t at index kBefore)
  };

  // At the start of the data (or after a pause) tracks are born without velocities, and a fast
  // limb's dense cluster can come out jumbled in its first frames. With kStartRows rows in hand,
  // each row from the last but two back to the first is labelled again by where each column's
  // next two rows put its marker (p(t) ~ 2 p(t+1) - p(t+2)), then the boundaries are judged.
  static constexpr size_t kStartRows = 16;
  void JudgeStart();
  void LabelStartBackward();
  // Judges the boundary before rows_[t] with `before` rows before it (2, or 1 at the start), in
  // four stages:
  void JudgeBoundary(size_t t, int before);
  // Fills present_, window_ and columns_ with the columns present across the boundary; false
  // when fewer than two are.
  bool GatherColumns(size_t t, int first);
  // Each column's jumps (acceleration at the boundary) and bends (its steady distances broken).
  void MarkJumpsAndBends(int first, int before);
  // Pairs traded for one or two frames, traded back, best gain first.
  struct ShortTrade {
    size_t i = 0, j = 0;  // columns_ indices
    int frames = 0;       // 0: none found
    double gain = 0.0;
  };
  void UndoShortTrades(size_t t, int first);
  bool BestShortTrade(int first, ShortTrade* best) const;
  // Jumping columns and their close neighbours reassigned for good, past to future.
  void TradeForGood(size_t t, int before);
  // Roughness where `past`'s rows before the boundary continue into `future`'s.
  double JoinCost(const Column& past, const Column& future, int before) const;
  // Close at the row before the boundary (options_.pair_radius_mm).
  bool Close(const Column& a, const Column& b) const;
  // A column's position in window row k (nullptr where it has none), for RigidExcess.
  struct OwnRows {
    const HindsightSwaps* self;
    const Column* column;
    const Eigen::Vector3d* operator()(int k) const {
      return self->present_[column->label] >> k & 1 ? &column->positions[k] : nullptr;
    }
  };
  OwnRows Own(const Column& column) const { return OwnRows{this, &column}; }
  // The optimal assignment of `cost` (rows: items, each column the item whose data would join it;
  // the identity always allowed): each of its cycles that removes most of the identity's cost is
  // accepted, label[item_labels_[column]] = item_labels_[row]. Returns the cycles accepted.
  // `judge`, when given, costs each cycle instead (items as they are, and taking what chosen says).
  using CycleJudge = std::function<void(const std::vector<size_t>& cycle, const std::vector<int>& chosen,
                                        double* as_is, double* then)>;
  int AcceptCycles(const Eigen::MatrixXd& cost, std::vector<int>* label, const CycleJudge& judge = nullptr);
  // Samples of rows [from_row, to_row) take label_of_column[their column].
  void Relabel(size_t from_row, size_t to_row, const std::vector<int>& label_of_column);
  // From from_row on, for the rows held and every later sample.
  void RelabelForGood(size_t from_row, const std::vector<int>& label_of_column);
  void Emit(size_t rows);
  int IssueColumn();
  void Place(int column, TrackSample sample);
  int ColumnForNewMarker(int marker, const std::vector<TrackSample>& samples);
  // Squared excess over the steady distances of columns_[i]'s neighbours (but `skip`) in window
  // rows [from, to) where its marker would be at position_at(k) (nullptr: absent), weighted
  // by options_.rigid_weight. takes[column] (when given, by column): the columns_ index whose
  // rows a neighbour takes (-1: its own).
  template <class PositionAt>
  double RigidExcess(size_t i, int from, int to, int skip, PositionAt position_at,
                     const std::vector<int>* takes = nullptr) const;

  HindsightSwapOptions options_;
  Sink sink_;
  std::deque<Row> rows_;
  // The tracker's marker -> output column, or one of:
  static constexpr int kNoColumn = -1;         // not seen yet
  static constexpr int kColumnGivenAway = -2;  // lost, and its column continued by a new marker
  std::vector<int> column_of_marker_;
  // By column (their count is the columns issued): the last frame placed and its position.
  static constexpr uint64_t kNever = ~uint64_t{0};
  static constexpr uint64_t kJoinFrames = 12;
  std::vector<uint64_t> last_frame_of_column_;
  std::vector<Eigen::Vector3d> last_position_of_column_;
  std::vector<int> new_markers_;  // Add's scratch
  long long columns_joined_ = 0;
  uint64_t last_sent_ = 0;
  bool sent_any_ = false;
  bool started_ = false;  // the first rows after the data's start (or a pause) were judged
  long long swaps_undone_ = 0;
  std::vector<TrackSample> late_;
  SteadyDistances distances_;
  // JudgeBoundary's scratch.
  std::vector<int> present_;  // by column
  std::vector<Eigen::Vector3d> window_;  // [k * columns + column]: valid where present_ says
  std::vector<Column> columns_;
  std::vector<std::vector<SteadyDistances::Neighbour>> neighbours_;  // by columns_ index
  std::vector<int> group_;
  std::vector<int> item_labels_;  // AcceptCycles' items' labels
  std::vector<size_t> cycle_;     // AcceptCycles' scratch
  std::vector<int> takes_;        // by column, the judge's
  static constexpr double kForbidden = 1e30;
  static constexpr double kBentExcess = 16.0;  // mm^2, unweighted
};

}  // namespace mocap

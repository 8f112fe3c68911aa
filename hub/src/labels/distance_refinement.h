// The runs' names as a whole, by their distances (the offline labeller's refinement): swaps of
// two runs' names, and moves to a name no overlapping run holds, while they lower the total cost
// (local search on the quadratic assignment the distances pose). Fixes what the mean shape gets
// wrong along a chain of markers that moves far from its mean pose (an arm serving), where the
// distances are right. Then the anchors' frame decides inside a segment, and names that cannot
// be told apart or fit worse than none are taken back.
#pragma once
#include <cstdint>
#include <map>
#include <utility>
#include <vector>

#include "io/marker_trajectories.h"
#include "labels/label_runs.h"
#include "labels/marker_set.h"
#include "labels/segment_frames.h"

namespace mocap {

struct DistanceRefinementOptions {
  // More runs than this are left as named (pairs grow with the square).
  size_t max_runs = 2000;
  // Frames at the ends of two runs that may both hold one name after an exchange.
  size_t boundary_frames = 5;
  // A run left without a name costs this per named run it meets (the mean pair cost that makes a
  // name not worth giving).
  double unnamed_pair_cost = 4.0;
  // Renames by the anchors' frame, and exchanges that cannot be told apart: the total may rise by
  // less than this per run.
  double ambiguity_margin = 2.0;
  // A run's votes favour a name clearly: this share of at least min_frame_votes votes.
  double clear_share = 0.75;
  double min_frame_votes = 20.0;
  void Check() const;  // std::invalid_argument naming the field and value
};

class DistanceRefinement {
 public:
  // run_at[f * columns + c]: the run of column c at frame f (-1: none). The runs' labels are
  // changed in place.
  DistanceRefinement(const MarkerTrajectories& in, const MarkerSet& set, const std::vector<SegmentAnchors>& anchors,
                     const std::vector<int64_t>& run_at, std::vector<Run>* runs,
                     const DistanceRefinementOptions& options = {});
  // Refines the names; taken[label]: the (first, last) frames of each run holding it. Returns the
  // share of a distance the subject's markers may differ from the set's.
  double Refine(std::vector<std::vector<std::pair<size_t, size_t>>>* taken);

 private:
  void MeasurePairs();
  // How well the set's distances fit this subject: the spread of the ratio of steady pairs'
  // distances (as named now) to the set's. The same subject: about 1 %; another: 10-20 %.
  void EstimateRelative();
  // Run i's cost with `label`: its distances to every other named run (run `skip` as if named
  // skip_label), and a little for straying from the name its frames supported.
  double CostOf(size_t i, int label, size_t skip, int skip_label) const;
  // No run overlapping run i (but i and `ignore`) holds `label`.
  bool FreeFor(int label, size_t i, size_t ignore) const;
  // The same for an exchange of two runs' names, but for a few frames at either end: where the
  // tracker swapped two markers is known to a few frames only.
  bool FreeForExchange(int label, size_t i, size_t ignore) const;
  double UnnamedCost(size_t i) const;
  double TotalCost() const;
  bool IsShort(size_t i) const;
  // The long runs' names at once, by an assignment, while the total falls.
  void SettleLongRuns();
  // Exchanges and moves, longer runs first, until nothing improves.
  void LocalSearch();
  // Each run's votes over its frames in its segment's anchor frame.
  std::vector<std::map<int, double>> SegmentFrameVotes() const;
  void RenameBySegmentVotes(const std::vector<std::map<int, double>>& votes, std::vector<char>* confirmed);
  void DropAmbiguous(const std::vector<char>& confirmed);
  void DropPoorFits();
  const RunPair& Pair(size_t i, size_t j) const { return pairs_[i * count_ + j]; }

  const MarkerTrajectories& in_;
  const MarkerSet& set_;
  const std::vector<SegmentAnchors>& anchors_;
  const std::vector<int64_t>& run_at_;
  std::vector<Run>& runs_;
  const DistanceRefinementOptions options_;
  const size_t count_;
  std::vector<RunPair> pairs_;  // [i * count_ + j]
  double relative_ = 0.1;
};

}  // namespace mocap

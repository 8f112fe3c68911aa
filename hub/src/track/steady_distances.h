// Steady distances between close output columns, learned from labelled rows: the shape of the
// rigid clusters a trajectory belongs to. Markers on one plate or segment keep their distances
// to a fraction of a millimetre while they can accelerate hard; a labelling that keeps them is
// the markers' own, one that bends them has traded two of them. Used by the hindsight swap
// repair, which learns from the rows it emits (final labels) and judges the rows it holds.
//
// Each pair of columns seen within `radius_mm` is learned: a running mean and variance of its
// distance (Welford), followed at any distance once learned. New pairs are found by a sweep along
// one axis, so that a row costs about its close pairs rather than all its pairs (7503 for 123
// markers). A pair whose distance varies by more than noise while it is learned, or drifts away
// from its steady distance for kMaxDrift frames, has a joint between its markers and is never
// steady again. A distance that steps (from one frame to the next) away from the learned
// one is a change of labels: kMaxStrays frames of it start the learning again from there, as
// does a step while it is learned. Steady: kMinSamples samples, standard deviation under
// max_sd_mm. Memory: one entry per pair that came close, forgotten after kForgetFrames frames
// unseen. Single-threaded; never throws.
#pragma once

#include <cstdint>
#include <unordered_map>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "track/tracker.h"

namespace mocap {

class SteadyDistances {
 public:
  struct Neighbour {
    int column = 0;
    double mean_mm = 0.0;
    double tolerance_mm = 0.0;  // deviations within it are noise
  };

  SteadyDistances(double radius_mm, double max_sd_mm, double min_tolerance_mm)
      : radius_mm_(radius_mm), max_sd_mm_(max_sd_mm), min_tolerance_mm_(min_tolerance_mm) {}

  // One labelled row (each column at most once), frames in increasing order; only measured
  // samples are learned.
  void Learn(uint64_t frame_number, const std::vector<TrackSample>& row);

  // The columns with a steady distance to `column`, into *out (cleared first), in the order their
  // pairs were first seen (within a row: by the samples' positions in it).
  void SteadyNeighbours(int column, std::vector<Neighbour>* out) const;

  // Squared excess of `distance_mm` beyond the neighbour's tolerance (0 within it).
  static double Excess(const Neighbour& neighbour, double distance_mm);

  size_t num_pairs() const { return pairs_.size(); }
  // Pair distances the last Learn computed: the known pairs whose columns were both measured,
  // and the pairs a sweep along one axis found near each other there (not all pairs of the row).
  size_t distances_computed() const { return distances_computed_; }

  static constexpr int kMinSamples = 10;
  static constexpr int kMaxStrays = 30;
  static constexpr int kMaxDrift = 3;
  static constexpr uint64_t kForgetFrames = 1000;

 private:
  struct Pair {
    int samples = 0;
    double mean = 0.0;
    double m2 = 0.0;
    int strays = 0;  // frames in a row away from a steady distance after a step
    int drift = 0;   // frames in a row away from it without one
    uint64_t last_frame = 0;
    double last_distance = 0.0;
    bool broken = false;
  };
  struct Partner {
    int column = 0;
    Pair* pair = nullptr;  // in pairs_
  };
  struct SweepEntry {
    Eigen::Vector3d position;
    int row = 0;  // position in the row
  };
  struct NewPair {
    int first = 0, second = 0;  // row positions, first < second
    double distance2 = 0.0;
  };
  void ObserveKnownPairs(uint64_t frame_number, const std::vector<TrackSample>& row);
  void LearnNewPairs(uint64_t frame_number, const std::vector<TrackSample>& row);
  bool Known(int a, int b) const;
  void Observe(Pair* pair, uint64_t frame_number, double distance) const;
  bool Steady(const Pair& pair) const;
  double Tolerance(const Pair& pair) const;
  static uint64_t Key(int a, int b) {
    return a < b ? (static_cast<uint64_t>(a) << 32) | static_cast<uint32_t>(b)
                 : (static_cast<uint64_t>(b) << 32) | static_cast<uint32_t>(a);
  }
  void ForgetOld(uint64_t frame_number);

  double radius_mm_;
  double max_sd_mm_;
  double min_tolerance_mm_;
  std::unordered_map<uint64_t, Pair> pairs_;
  std::vector<std::vector<Partner>> partners_;  // by column: the columns it has a pair entry with
  uint64_t last_sweep_ = 0;
  size_t distances_computed_ = 0;
  // Scratch of Learn, kept to spare allocations: the row positions of measured samples, the row
  // position of each column's sample (-1: none), the sweep's order, and the pairs first seen in
  // the row.
  std::vector<int> measured_;
  std::vector<int> row_of_column_;
  std::vector<SweepEntry> sweep_;
  std::vector<NewPair> new_pairs_;
};

}  // namespace mocap

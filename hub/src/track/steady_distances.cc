// Running distance statistics of close column pairs.
#include "track/steady_distances.h"

#include <algorithm>
#include <cmath>

#include "util/running_variance.h"

namespace mocap {

bool SteadyDistances::Steady(const Pair& pair) const {
  return pair.samples >= kMinSamples && pair.m2 <= max_sd_mm_ * max_sd_mm_ * (pair.samples - 1);
}

double SteadyDistances::Tolerance(const Pair& pair) const {
  const double sd = pair.samples > 1 ? std::sqrt(pair.m2 / (pair.samples - 1)) : 0.0;
  return std::max(min_tolerance_mm_, 4.0 * sd);
}

double SteadyDistances::Excess(const Neighbour& neighbour, double distance_mm) {
  const double beyond = std::abs(distance_mm - neighbour.mean_mm) - neighbour.tolerance_mm;
  return beyond > 0.0 ? beyond * beyond : 0.0;
}

void SteadyDistances::Learn(uint64_t frame_number, const std::vector<TrackSample>& row) {
  measured_.clear();
  for (size_t i = 0; i < row.size(); ++i) {
    // A measured sample is a triangulated point, so finite; one that is not has no distance.
    if (row[i].kind == SampleKind::kMeasured && row[i].marker >= 0 && row[i].position.allFinite()) {
      measured_.push_back(static_cast<int>(i));
    }
  }
  distances_computed_ = 0;
  ObserveKnownPairs(frame_number, row);
  LearnNewPairs(frame_number, row);
  ForgetOld(frame_number);
}

void SteadyDistances::ObserveKnownPairs(uint64_t frame_number, const std::vector<TrackSample>& row) {
  // A known pair is observed at whatever distance, so that it can drift apart and break.
  row_of_column_.assign(partners_.size(), -1);
  for (int i : measured_) {
    if (static_cast<size_t>(row[i].marker) < partners_.size()) row_of_column_[row[i].marker] = i;
  }
  for (int i : measured_) {
    const int a = row[i].marker;
    if (static_cast<size_t>(a) >= partners_.size()) continue;
    for (const Partner& partner : partners_[a]) {
      const int j = partner.column < a ? -1 : row_of_column_[partner.column];  // each pair once
      if (j < 0) continue;
      ++distances_computed_;
      // The same bits whichever sample comes first: a difference's negation is exact.
      Observe(partner.pair, frame_number, std::sqrt((row[i].position - row[j].position).squaredNorm()));
    }
  }
}

bool SteadyDistances::Known(int a, int b) const {
  const std::vector<Partner>& list = partners_[a];  // a short list: the columns that came close
  return std::any_of(list.begin(), list.end(), [b](const Partner& p) { return p.column == b; });
}

void SteadyDistances::LearnNewPairs(uint64_t frame_number, const std::vector<TrackSample>& row) {
  const double radius2 = radius_mm_ * radius_mm_;
  // Sweep along the axis the row spreads most on: sorted by that coordinate, a sample's pairs
  // within the radius are among the next ones, up to the first farther than the radius along it
  // (a squared distance is a sum of non-negative squares, rounded: never below its term on the
  // axis).
  Eigen::Vector3d low = Eigen::Vector3d::Constant(HUGE_VAL), high = -low;
  sweep_.clear();
  for (int i : measured_) {
    low = low.cwiseMin(row[i].position);
    high = high.cwiseMax(row[i].position);
    sweep_.push_back({row[i].position, i});
  }
  int axis = 0;
  (high - low).maxCoeff(&axis);  // the first of equal spreads
  std::sort(sweep_.begin(), sweep_.end(),
            [axis](const SweepEntry& x, const SweepEntry& y) { return x.position[axis] < y.position[axis]; });

  new_pairs_.clear();
  const auto consider = [&](int i, int j, double distance2) {
    const int a = row[i].marker, b = row[j].marker;
    if (a == b || distance2 > radius2) return;
    if (static_cast<size_t>(std::max(a, b)) < partners_.size() && Known(a, b)) return;  // observed already
    new_pairs_.push_back({std::min(i, j), std::max(i, j), distance2});
  };
  for (size_t k = 0; k < sweep_.size(); ++k) {
    const SweepEntry& first = sweep_[k];
    for (size_t l = k + 1; l < sweep_.size(); ++l) {
      const double along = sweep_[l].position[axis] - first.position[axis];
      if (along * along > radius2) break;
      ++distances_computed_;
      consider(first.row, sweep_[l].row, (first.position - sweep_[l].position).squaredNorm());
    }
  }


  // New pairs enter in row order (as a walk over the row's pairs finds them): each column's
  // partners, and so the order of its steady neighbours, do not depend on the sweep.
  std::sort(new_pairs_.begin(), new_pairs_.end(), [](const NewPair& x, const NewPair& y) {
    return x.first != y.first ? x.first < y.first : x.second < y.second;
  });
  for (const NewPair& n : new_pairs_) {
    const int a = row[n.first].marker, b = row[n.second].marker;
    const auto [entry, fresh] = pairs_.emplace(Key(a, b), Pair());
    if (fresh) {  // (not fresh only for a row that breaks the one-sample-per-column rule)
      // Elements of an unordered_map stay where they are as it grows: partners keep the address.
      const size_t needed = static_cast<size_t>(std::max(a, b)) + 1;
      if (partners_.size() < needed) partners_.resize(needed);
      partners_[a].push_back({b, &entry->second});
      partners_[b].push_back({a, &entry->second});
    }
    Observe(&entry->second, frame_number, std::sqrt(n.distance2));
  }
}

void SteadyDistances::Observe(Pair* pair, uint64_t frame_number, double distance) const {
  const bool consecutive = pair->samples > 0 && pair->last_frame + 1 == frame_number;
  const double previous = pair->last_distance;
  pair->last_frame = frame_number;
  pair->last_distance = distance;
  if (pair->broken) return;
  const auto restart = [&]() { *pair = Pair{1, distance, 0.0, 0, 0, frame_number, distance, false}; };
  // A step from the last frame's distance beyond what noise makes (4 sd of a steady pair): the
  // labels changed (or a point was misplaced).
  const bool step = consecutive && std::abs(distance - previous) > 4.0 * max_sd_mm_;
  if (!Steady(*pair)) {
    if (step || pair->samples == 0) return restart();
    if (pair->samples >= kMinSamples) {
      pair->broken = true;  // it moves: no rigid pair
      return;
    }
  } else if (std::abs(distance - pair->mean) > Tolerance(*pair)) {
    // Away from a steady distance: by a step, it is a labelling to wait out or learn anew;
    // drifting away for kMaxDrift frames, the pair bends (a joint between the two).
    if (step || pair->strays > 0) {
      if (++pair->strays >= kMaxStrays) restart();
    } else if (++pair->drift >= kMaxDrift) {
      pair->broken = true;
    }
    return;
  }
  pair->strays = 0;
  pair->drift = 0;
  AddToRunningVariance(distance, &pair->samples, &pair->mean, &pair->m2);
}

void SteadyDistances::ForgetOld(uint64_t frame_number) {
  if (frame_number < last_sweep_ + kForgetFrames) return;
  last_sweep_ = frame_number;
  for (auto it = pairs_.begin(); it != pairs_.end();) {
    if (it->second.last_frame + kForgetFrames > frame_number) {
      ++it;
      continue;
    }
    const int a = static_cast<int>(it->first >> 32), b = static_cast<int>(it->first & 0xffffffffu);
    for (auto [from, to] : {std::pair<int, int>{a, b}, std::pair<int, int>{b, a}}) {
      std::vector<Partner>& list = partners_[from];
      list.erase(std::remove_if(list.begin(), list.end(), [to = to](const Partner& p) { return p.column == to; }),
                 list.end());
    }
    it = pairs_.erase(it);
  }
}

void SteadyDistances::SteadyNeighbours(int column, std::vector<Neighbour>* out) const {
  out->clear();
  if (column < 0 || static_cast<size_t>(column) >= partners_.size()) return;
  for (const Partner& partner : partners_[column]) {
    const Pair& pair = *partner.pair;
    if (!pair.broken && Steady(pair)) out->push_back({partner.column, pair.mean, Tolerance(pair)});
  }
}

}  // namespace mocap

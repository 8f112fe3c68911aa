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
  const double radius2 = radius_mm_ * radius_mm_;
  for (size_t i = 0; i < row.size(); ++i) {
    if (row[i].kind != SampleKind::kMeasured) continue;
    for (size_t j = i + 1; j < row.size(); ++j) {
      if (row[j].kind != SampleKind::kMeasured) continue;
      const int a = row[i].marker, b = row[j].marker;
      if (a == b || a < 0 || b < 0) continue;
      const double distance2 = (row[i].position - row[j].position).squaredNorm();
      auto found = pairs_.find(Key(a, b));
      if (found == pairs_.end()) {
        if (distance2 > radius2) continue;
        found = pairs_.emplace(Key(a, b), Pair()).first;
        const size_t needed = static_cast<size_t>(std::max(a, b)) + 1;
        if (partners_.size() < needed) partners_.resize(needed);
        partners_[a].push_back(b);
        partners_[b].push_back(a);
      }
      Observe(&found->second, frame_number, std::sqrt(distance2));
    }
  }
  ForgetOld(frame_number);
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
      std::vector<int>& list = partners_[from];
      list.erase(std::remove(list.begin(), list.end(), to), list.end());
    }
    it = pairs_.erase(it);
  }
}

void SteadyDistances::SteadyNeighbours(int column, std::vector<Neighbour>* out) const {
  out->clear();
  if (column < 0 || static_cast<size_t>(column) >= partners_.size()) return;
  for (int other : partners_[column]) {
    const Pair& pair = pairs_.at(Key(column, other));
    if (!pair.broken && Steady(pair)) out->push_back({other, pair.mean, Tolerance(pair)});
  }
}

}  // namespace mocap

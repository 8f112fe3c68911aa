// Labelling a whole recording (see trial_labeller.h).
#include "labels/trial_labeller.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <tuple>

namespace mocap {
namespace {

struct Run {
  size_t column = 0;
  size_t first = 0, last = 0;  // frame indices, inclusive
  std::map<int, double> support;
  double total = 0.0;
  int label = -1;
};

// Distance statistics of two runs over the frames they share.
struct RunPair {
  double mean = 0.0, sd = 0.0;
  int frames = 0;
};

// How far two runs' distance is from what the set says of their names: in units of the spread
// the set and the runs allow (another subject's markers sit elsewhere: a tenth of the distance),
// squared and capped so that one odd pair cannot outweigh the rest.
double PairCost(const MarkerSet& set, int a, int b, const RunPair& pair) {
  if (a < 0 || b < 0 || pair.frames < 10) return 0.0;
  const MarkerDistance* d = set.Distance(a, b);
  if (d == nullptr) return 0.0;
  const double z = (pair.mean - d->mean) / (d->sd + pair.sd + 3.0 + 0.1 * d->mean);
  return std::min(z * z, 25.0);
}

// The runs' names as a whole, by their distances: swaps of two runs' names, and moves to a name no
// overlapping run holds, while they lower the total cost (local search on the quadratic
// assignment the distances pose). Fixes what the mean shape gets wrong along a chain of markers
// that moves far from its mean pose (an arm serving), where the distances are right.
void RefineByDistances(const MarkerTrajectories& in, const MarkerSet& set, const std::vector<int64_t>& run_at,
                       std::vector<Run>* runs_in, std::vector<std::vector<std::pair<size_t, size_t>>>* taken) {
  std::vector<Run>& runs = *runs_in;
  const size_t r_count = runs.size();
  if (r_count < 2 || r_count > 2000) return;  // bounded: pairs grow with the square
  const size_t columns = in.NumMarkers();
  std::vector<RunPair> pairs(r_count * r_count);
  std::vector<double> sum(r_count * r_count, 0.0), sum_squares(r_count * r_count, 0.0);
  std::vector<int64_t> present;
  for (size_t f = 0; f < in.NumFrames(); ++f) {
    present.clear();
    for (size_t c = 0; c < columns; ++c)
      if (run_at[f * columns + c] >= 0) present.push_back(static_cast<int64_t>(c));
    for (size_t x = 0; x < present.size(); ++x)
      for (size_t y = x + 1; y < present.size(); ++y) {
        size_t i = static_cast<size_t>(run_at[f * columns + static_cast<size_t>(present[x])]);
        size_t j = static_cast<size_t>(run_at[f * columns + static_cast<size_t>(present[y])]);
        if (i > j) std::swap(i, j);
        const double d = (in.At(f, static_cast<size_t>(present[x])) - in.At(f, static_cast<size_t>(present[y]))).norm();
        sum[i * r_count + j] += d, sum_squares[i * r_count + j] += d * d, ++pairs[i * r_count + j].frames;
      }
  }
  for (size_t i = 0; i < r_count; ++i)
    for (size_t j = i + 1; j < r_count; ++j) {
      RunPair& p = pairs[i * r_count + j];
      if (p.frames == 0) continue;
      p.mean = sum[i * r_count + j] / p.frames;
      p.sd = std::sqrt(std::max(0.0, sum_squares[i * r_count + j] / p.frames - p.mean * p.mean));
      pairs[j * r_count + i] = p;
    }
  // A run's cost with a name: its distances to every other named run, and a little for straying
  // from the name its frames supported.
  auto cost_of = [&](size_t i, int label, size_t skip, int skip_label) {
    double c = 0.0;
    for (size_t j = 0; j < r_count; ++j) {
      if (j == i) continue;
      const int other = j == skip ? skip_label : runs[j].label;
      c += PairCost(set, label, other, pairs[i * r_count + j]);
    }
    const auto it = runs[i].support.find(label);
    const double share = runs[i].total > 0.0 && it != runs[i].support.end() ? it->second / runs[i].total : 0.0;
    return c + 2.0 * (1.0 - share);
  };
  auto free_for = [&](int label, size_t i, size_t ignore) {
    for (size_t j = 0; j < r_count; ++j)
      if (j != i && j != ignore && runs[j].label == label && runs[i].first <= runs[j].last && runs[j].first <= runs[i].last)
        return false;
    return true;
  };
  for (int sweep = 0; sweep < 20; ++sweep) {
    bool improved = false;
    for (size_t i = 0; i < r_count; ++i) {
      if (runs[i].label < 0) continue;
      for (size_t j = i + 1; j < r_count; ++j) {
        if (runs[j].label < 0 || runs[i].label < 0) continue;
        const int li = runs[i].label, lj = runs[j].label;
        if (!free_for(lj, i, j) || !free_for(li, j, i)) continue;
        const double before = cost_of(i, li, j, lj) + cost_of(j, lj, i, li);
        const double after = cost_of(i, lj, j, li) + cost_of(j, li, i, lj);
        if (after < before - 1e-6) {
          runs[i].label = lj, runs[j].label = li;
          improved = true;
        }
      }
      for (int u = 0; u < static_cast<int>(set.NumMarkers()); ++u) {
        const int li = runs[i].label;
        if (u == li || !free_for(u, i, i)) continue;
        if (cost_of(i, u, i, u) < cost_of(i, li, i, li) - 1e-6) {
          runs[i].label = u;
          improved = true;
        }
      }
    }
    if (!improved) break;
  }
  for (auto& t : *taken) t.clear();
  for (const Run& run : runs)
    if (run.label >= 0) (*taken)[static_cast<size_t>(run.label)].push_back({run.first, run.last});
}

}  // namespace

TrialLabelling LabelTrajectories(const MarkerTrajectories& in, const MarkerSet& set, const LabellerOptions& options) {
  MarkerLabeller labeller(set, options);
  const size_t columns = in.NumMarkers();
  std::vector<Run> runs;
  std::vector<int64_t> run_of_column(columns, -1);
  std::vector<int64_t> run_at(in.points.size(), -1);  // per (frame, column)
  std::vector<Eigen::Vector3d> points;
  std::vector<int64_t> tracks;
  std::vector<size_t> column_of_point;
  std::vector<char> broken(columns, 0);
  for (size_t f = 0; f < in.NumFrames(); ++f) {
    points.clear(), tracks.clear(), column_of_point.clear();
    for (size_t c = 0; c < columns; ++c) {
      if (!in.Has(f, c)) {
        run_of_column[c] = -1;
        continue;
      }
      if (run_of_column[c] < 0 || broken[c]) {
        run_of_column[c] = static_cast<int64_t>(runs.size());
        runs.push_back(Run{c, f, f, {}, 0.0, -1});
        broken[c] = 0;
      }
      Run& run = runs[static_cast<size_t>(run_of_column[c])];
      run.last = f;
      run_at[f * columns + c] = run_of_column[c];
      points.push_back(in.At(f, c));
      tracks.push_back(run_of_column[c]);
      column_of_point.push_back(c);
    }
    const std::vector<int>& labels = labeller.Update(points, tracks);
    const std::vector<int>& proposals = labeller.proposals();
    for (size_t p = 0; p < points.size(); ++p) {
      Run& run = runs[static_cast<size_t>(tracks[p])];
      // A frame holding a name counts twice a vote: it passed the swap guard.
      if (labels[p] >= 0) run.support[labels[p]] += 2.0, run.total += 2.0;
      if (proposals[p] >= 0) run.support[proposals[p]] += 1.0, run.total += 1.0;
      if (labels[p] < 0 && proposals[p] < 0) run.total += 1.0;
    }
    for (int64_t track : labeller.revoked()) broken[runs[static_cast<size_t>(track)].column] = 1;
  }

  // One name per run: the best supported first, never two overlapping runs with one name.
  std::vector<std::tuple<double, size_t, int>> candidates;  // (support, run, label)
  for (size_t r = 0; r < runs.size(); ++r)
    for (const auto& [label, support] : runs[r].support)
      if (2.0 * support >= runs[r].total) candidates.emplace_back(support, r, label);
  std::sort(candidates.begin(), candidates.end(), [](const auto& x, const auto& y) { return std::get<0>(x) > std::get<0>(y); });
  std::vector<std::vector<std::pair<size_t, size_t>>> taken(set.NumMarkers());
  TrialLabelling out;
  out.runs = runs.size();
  for (const auto& [support, r, label] : candidates) {
    Run& run = runs[r];
    if (run.label >= 0) continue;
    bool overlaps = false;
    for (const auto& [first, last] : taken[static_cast<size_t>(label)])
      overlaps = overlaps || (run.first <= last && first <= run.last);
    if (overlaps) continue;
    run.label = label;
    taken[static_cast<size_t>(label)].push_back({run.first, run.last});
    ++out.named_runs;
  }

  RefineByDistances(in, set, run_at, &runs, &taken);

  // Columns: the names placed, in the set's order, then the input columns left with data.
  std::vector<int> column_of_label(set.NumMarkers(), -1);
  MarkerTrajectories& named = out.named;
  named.rate_hz = in.rate_hz;
  for (size_t a = 0; a < set.NumMarkers(); ++a)
    if (!taken[a].empty()) {
      column_of_label[a] = static_cast<int>(named.names.size());
      named.names.push_back(set.names[a]);
    }
  out.names_placed = named.names.size();
  std::vector<int> leftover_column(columns, -1);
  for (const Run& run : runs)
    if (run.label < 0 && leftover_column[run.column] < 0) leftover_column[run.column] = 0;
  for (size_t c = 0; c < columns; ++c)
    if (leftover_column[c] == 0) {
      leftover_column[c] = static_cast<int>(named.names.size());
      named.names.push_back(in.names[c]);
    }
  for (size_t f = 0; f < in.NumFrames(); ++f) {
    const size_t row = named.AddFrame(in.frame_numbers[f]);
    for (size_t c = 0; c < columns; ++c) {
      const int64_t r = run_at[f * columns + c];
      if (r < 0) continue;
      const Run& run = runs[static_cast<size_t>(r)];
      const int column = run.label >= 0 ? column_of_label[static_cast<size_t>(run.label)] : leftover_column[c];
      named.At(row, static_cast<size_t>(column)) = in.At(f, c);
      ++out.points;
      out.named_points += run.label >= 0;
    }
  }
  out.stats = labeller.stats();
  return out;
}

}  // namespace mocap

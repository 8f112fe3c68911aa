// Marker-set learning (see marker_set_learning.h).
#include "labels/marker_set_learning.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <unordered_map>

#include "labels/shape_fit.h"

namespace mocap {

void MarkerSetLearnOptions::Check() const {
  if (!(rigid_sd_mm > 0.0 && rigid_sd_mm < 1000.0)) throw std::invalid_argument("rigid sd must be in (0, 1000) mm");
  if (!(max_segment_mm > 0.0 && max_segment_mm < 1e5)) throw std::invalid_argument("segment size must be in (0, 1e5) mm");
  if (min_pair_frames < 2) throw std::invalid_argument("min pair frames must be >= 2");
  if (up_axis < -1 || up_axis > 2) throw std::invalid_argument("up axis must be 0, 1, 2 or -1");
}

Eigen::Matrix3d UpToZ(int up_axis) {
  Eigen::Matrix3d r = Eigen::Matrix3d::Zero();
  // Cyclic permutations keep the handedness: (x, y, z) -> (y, z, x) puts x up, (z, x, y) puts y up.
  const int order[3][3] = {{1, 2, 0}, {2, 0, 1}, {0, 1, 2}};
  for (int row = 0; row < 3; ++row) r(row, order[up_axis][row]) = 1.0;
  return r;
}

namespace {

struct PairAccumulator {
  double sum = 0.0, sum_squares = 0.0, min = 1e300, max = -1e300;
  size_t n = 0;
  void Add(double d) {
    sum += d, sum_squares += d * d, ++n;
    min = std::min(min, d), max = std::max(max, d);
  }
};

// Complete-linkage clusters of markers whose every pair is steady and near.
std::vector<std::vector<int>> Segments(const MarkerSet& set, const MarkerSetLearnOptions& options) {
  const size_t n = set.NumMarkers();
  auto steady = [&](int a, int b) {
    const MarkerDistance* d = set.Distance(a, b);
    return d != nullptr && d->sd <= options.rigid_sd_mm && d->mean <= options.max_segment_mm;
  };
  std::vector<std::pair<double, std::pair<int, int>>> pairs;
  for (const MarkerDistance& d : set.distances)
    if (steady(d.a, d.b)) pairs.push_back({d.sd, {d.a, d.b}});
  std::sort(pairs.begin(), pairs.end());
  std::vector<int> cluster(n);
  std::vector<std::vector<int>> members(n);
  for (size_t i = 0; i < n; ++i) cluster[i] = static_cast<int>(i), members[i] = {static_cast<int>(i)};
  for (const auto& [sd, ab] : pairs) {
    const int ca = cluster[static_cast<size_t>(ab.first)], cb = cluster[static_cast<size_t>(ab.second)];
    if (ca == cb) continue;
    bool all = true;
    for (int x : members[static_cast<size_t>(ca)])
      for (int y : members[static_cast<size_t>(cb)]) all = all && steady(x, y);
    if (!all) continue;
    for (int y : members[static_cast<size_t>(cb)]) {
      cluster[static_cast<size_t>(y)] = ca;
      members[static_cast<size_t>(ca)].push_back(y);
    }
    members[static_cast<size_t>(cb)].clear();
  }
  std::vector<std::vector<int>> segments;
  for (std::vector<int>& m : members)
    if (m.size() >= 2) {
      std::sort(m.begin(), m.end());
      segments.push_back(m);
    }
  std::sort(segments.begin(), segments.end());
  return segments;
}

}  // namespace

namespace {

// The trials in the set's marker order, turned z-up: Load(t, f) fills frame and present.
class LearningTrials {
 public:
  LearningTrials(const std::vector<MarkerTrajectories>& trials, const std::vector<std::string>& sources,
                 const MarkerSetLearnOptions& options, MarkerSet* set)
      : trials_(trials), column_marker_(trials.size()), to_z_(trials.size()) {
    std::unordered_map<std::string, int> index;
    for (size_t t = 0; t < trials.size(); ++t) {
      const MarkerTrajectories& trial = trials[t];
      const std::string& source = t < sources.size() ? sources[t] : "trial " + std::to_string(t + 1);
      int up = options.up_axis;
      if (up < 0) up = DetectUpAxis(trial);
      if (up < 0) throw std::invalid_argument(source + ": no frame with three markers (cannot tell up)");
      to_z_[t] = UpToZ(up);
      for (const std::string& name : trial.names) {
        if (IsAnonymousMarkerName(name)) {
          column_marker_[t].push_back(-1);
          continue;
        }
        auto [it, added] = index.emplace(name, static_cast<int>(set->names.size()));
        if (added) set->names.push_back(name);
        column_marker_[t].push_back(it->second);
      }
    }
    frame.resize(set->names.size());
    present.resize(set->names.size());
  }
  size_t NumTrials() const { return trials_.size(); }
  size_t NumFrames(size_t t) const { return trials_[t].NumFrames(); }
  void Load(size_t t, size_t f) {
    std::fill(present.begin(), present.end(), 0);
    for (size_t c = 0; c < trials_[t].NumMarkers(); ++c) {
      const int m = column_marker_[t][c];
      if (m < 0 || !trials_[t].Has(f, c)) continue;
      frame[static_cast<size_t>(m)] = to_z_[t] * trials_[t].At(f, c);
      present[static_cast<size_t>(m)] = 1;
    }
  }
  std::vector<Eigen::Vector3d> frame;  // by set marker, valid where present
  std::vector<char> present;

 private:
  const std::vector<MarkerTrajectories>& trials_;
  std::vector<std::vector<int>> column_marker_;  // per trial: the set's marker of each column (-1: anonymous)
  std::vector<Eigen::Matrix3d> to_z_;
};

// Distances of every pair over every frame where both are present.
void LearnDistances(LearningTrials* trials, const MarkerSetLearnOptions& options, MarkerSet* set) {
  const size_t n = set->names.size();
  std::vector<PairAccumulator> acc(n * n);
  for (size_t t = 0; t < trials->NumTrials(); ++t)
    for (size_t f = 0; f < trials->NumFrames(t); ++f) {
      trials->Load(t, f);
      for (size_t a = 0; a < n; ++a)
        for (size_t b = a + 1; b < n && trials->present[a]; ++b)
          if (trials->present[b]) acc[a * n + b].Add((trials->frame[a] - trials->frame[b]).norm());
    }
  for (size_t a = 0; a < n; ++a)
    for (size_t b = a + 1; b < n; ++b) {
      const PairAccumulator& p = acc[a * n + b];
      if (p.n < options.min_pair_frames) continue;
      MarkerDistance d;
      d.a = static_cast<int>(a), d.b = static_cast<int>(b);
      d.mean = p.sum / static_cast<double>(p.n);
      d.sd = std::sqrt(std::max(0.0, p.sum_squares / static_cast<double>(p.n) - d.mean * d.mean));
      d.min = p.min, d.max = p.max, d.frames = p.n;
      d.mean = std::clamp(d.mean, d.min, d.max);  // rounding of a constant distance
      set->distances.push_back(d);
    }
}

// The trunk: markers whose distances to the others vary least (median sd), the steadiest 40 %.
std::vector<char> SteadiestCore(const MarkerSet& set) {
  const size_t n = set.names.size();
  std::vector<char> core(n, 0);
  std::vector<std::pair<double, size_t>> steadiness;
  for (size_t a = 0; a < n; ++a) {
    std::vector<double> sds;
    for (size_t b = 0; b < n; ++b)
      if (const MarkerDistance* d = set.Distance(static_cast<int>(a), static_cast<int>(b))) sds.push_back(d->sd);
    if (sds.empty()) continue;
    std::nth_element(sds.begin(), sds.begin() + sds.size() / 2, sds.end());
    steadiness.push_back({sds[sds.size() / 2], a});
  }
  std::sort(steadiness.begin(), steadiness.end());
  const size_t take = std::max<size_t>(3, (steadiness.size() * 4) / 10);
  for (size_t i = 0; i < steadiness.size() && i < take; ++i) core[steadiness[i].second] = 1;
  return core;
}

// Mean shape: frames turned about z onto a reference (the first trial's fullest frame),
// averaged, three rounds.
std::vector<Eigen::Vector3d> MeanShape(LearningTrials* trials, const std::vector<char>& core) {
  const size_t n = core.size();
  const std::vector<char>& present = trials->present;
  const std::vector<Eigen::Vector3d>& frame = trials->frame;
  std::vector<Eigen::Vector3d> reference(n, Eigen::Vector3d::Constant(std::nan("")));
  size_t best = 0;
  for (size_t f = 0; f < trials->NumFrames(0); ++f) {
    trials->Load(0, f);
    const size_t count = static_cast<size_t>(std::count(present.begin(), present.end(), 1));
    if (count > best) {
      best = count;
      for (size_t m = 0; m < n; ++m) reference[m] = present[m] ? frame[m] : Eigen::Vector3d::Constant(std::nan(""));
    }
  }
  for (int round = 0; round < 3; ++round) {
    std::vector<Eigen::Vector3d> sum(n, Eigen::Vector3d::Zero());
    std::vector<size_t> count(n, 0);
    std::vector<Eigen::Vector3d> source, target;
    for (size_t t = 0; t < trials->NumTrials(); ++t)
      for (size_t f = 0; f < trials->NumFrames(t); ++f) {
        trials->Load(t, f);
        source.clear(), target.clear();
        for (size_t m = 0; m < n; ++m)
          if (present[m] && reference[m].allFinite()) source.push_back(frame[m]), target.push_back(reference[m]);
        if (source.size() < 3) continue;
        // Limbs swing: the trunk's markers (the steadiest) set the frame's turn when enough of
        // them are present.
        std::vector<Eigen::Vector3d> core_source, core_target;
        for (size_t m = 0; m < n; ++m)
          if (present[m] && core[m] && reference[m].allFinite())
            core_source.push_back(frame[m]), core_target.push_back(reference[m]);
        const UprightTransform fit = core_source.size() >= 3 ? FitUpright(core_source, core_target, false)
                                                             : FitUpright(source, target, false);
        for (size_t m = 0; m < n; ++m)
          if (present[m]) sum[m] += fit.Apply(frame[m]), ++count[m];
      }
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    size_t known = 0;
    for (size_t m = 0; m < n; ++m)
      if (count[m] > 0) reference[m] = sum[m] / static_cast<double>(count[m]), centroid += reference[m], ++known;
    if (known == 0) throw std::invalid_argument("no frame shares three markers with the reference frame");
    centroid /= static_cast<double>(known);
    for (size_t m = 0; m < n; ++m)
      if (count[m] > 0) reference[m] -= centroid;
  }
  return reference;
}

}  // namespace

MarkerSet LearnMarkerSet(const std::vector<MarkerTrajectories>& trials, const std::vector<std::string>& sources,
                         const MarkerSetLearnOptions& options) {
  options.Check();
  if (trials.empty()) throw std::invalid_argument("no trials to learn from");
  MarkerSet set;
  LearningTrials learning(trials, sources, options, &set);
  const size_t n = set.names.size();
  if (n < 3) throw std::invalid_argument("the trials name fewer than 3 markers (anonymous M001... columns do not count)");
  if (n > kMaxMarkerSetMarkers) throw std::invalid_argument("more than " + std::to_string(kMaxMarkerSetMarkers) + " markers");
  LearnDistances(&learning, options, &set);
  set.mean_shape.assign(n, Eigen::Vector3d::Constant(std::nan("")));
  set.Index();
  set.segments = Segments(set, options);
  set.mean_shape = MeanShape(&learning, SteadiestCore(set));
  return set;
}

}  // namespace mocap

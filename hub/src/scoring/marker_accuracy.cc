// Metric computation for `eval`. Frames align by time (frame number / rate), so files written at
// different rates or with different Frame# numbering still compare the right instants.
#include "scoring/marker_accuracy.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <sstream>
#include <stdexcept>
#include <unordered_map>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "scoring/truth_exchanges.h"
#include "util/assignment.h"

namespace mocap {
namespace {

// Index of the truth frame at the result frame's instant, or -1. An instant matches when it is
// within a quarter of a truth frame period, tolerant of rounded Time columns.
long AlignedTruthFrame(const std::unordered_map<uint64_t, size_t>& truth_index, double truth_rate, double time) {
  const double position = time * truth_rate;
  const double nearest = std::round(position);
  if (nearest < 0.0 || std::abs(position - nearest) > 0.25) return -1;
  const auto it = truth_index.find(static_cast<uint64_t>(nearest));
  return it == truth_index.end() ? -1 : static_cast<long>(it->second);
}

}  // namespace

void MarkerEvalOptions::Check() const {
  if (!(gate_mm > 0.0 && gate_mm < 1e6)) throw std::invalid_argument("gate must be positive");
  if (min_cameras < 0) throw std::invalid_argument("min cameras must be >= 0");
  if (names_from_frame < 1) {
    throw std::invalid_argument("names_from_frame: " + std::to_string(names_from_frame) + " must be >= 1");
  }
}

namespace {

// EvaluateMarkers' state: the names and tracks of the result, the frames aligned, and what each
// track and truth marker did so far. Score() walks the truth frames once; Finish() turns the
// counts into the report's shares and error statistics.
class MarkerScorer {
 public:
  MarkerScorer(const MarkerTrajectories& truth, const MarkerTrajectories& result, const MarkerVisibility* visibility,
               const MarkerEvalOptions& options, const PublishedIdentity* identity);
  void Score();
  MarkerEvalReport Finish();

 private:
  struct TrackState {
    long last_match = -1;  // truth marker
    long last_name = -1;   // index into names
    size_t name_changes = 0;
  };
  void IndexNames();
  void AlignFrames();
  void ScoreFrame(size_t t);
  // One result point matched to truth `marker` (-1: none) at truth frame t.
  void ScorePoint(size_t t, size_t r, size_t column, long marker, size_t* frame_correct, size_t* frame_points);
  void CountExpected(size_t t, const std::vector<char>& truth_matched);
  // The result point's name (an index into names_, -1: unnamed) and track (dense, -1: none).
  long NameOf(size_t r, size_t column) const;
  long TrackOf(size_t r, size_t column);

  const MarkerTrajectories& truth_;
  const MarkerTrajectories& result_;
  const MarkerVisibility* visibility_;
  const MarkerEvalOptions& options_;
  const PublishedIdentity* identity_;
  const size_t truth_markers_, result_markers_;
  MarkerEvalReport report_;
  std::unordered_map<uint64_t, size_t> visibility_index_;
  // Names: each point's name is an index into names_; its truth marker (named_as_), -1 for a
  // name the truth does not have and for the hub's anonymous names.
  const std::vector<std::string>& names_;
  std::vector<long> named_as_;
  std::vector<char> anonymous_;
  bool labels_ = false;
  // Tracks: a column of a TRC, a published id of a live result (dense indices in order seen).
  std::unordered_map<int64_t, size_t> track_index_;
  std::vector<TrackState> tracks_;
  std::vector<long> result_of_truth_;  // by truth frame: the aligned result frame, or -1
  std::vector<char> truth_ever_;
  std::vector<long> truth_frames_present_;
  std::vector<long> last_track_of_marker_;
  std::vector<size_t> id_changes_of_marker_;
  TruthExchanges exchanges_;
  double worst_share_ = 1.0;
  std::vector<double> errors_;
  std::vector<size_t> present_truth_, present_result_;
};

MarkerScorer::MarkerScorer(const MarkerTrajectories& truth, const MarkerTrajectories& result,
                           const MarkerVisibility* visibility, const MarkerEvalOptions& options,
                           const PublishedIdentity* identity)
    : truth_(truth), result_(result), visibility_(visibility), options_(options), identity_(identity),
      truth_markers_(truth.NumMarkers()), result_markers_(result.NumMarkers()),
      names_(identity != nullptr ? identity->names : result.names),
      truth_ever_(truth_markers_, 0), truth_frames_present_(truth_markers_, 0),
      last_track_of_marker_(truth_markers_, -1), id_changes_of_marker_(truth_markers_, 0),
      exchanges_(FindTruthExchanges(truth)) {
  options.Check();
  if (!(truth.rate_hz > 0.0) || !(result.rate_hz > 0.0)) throw std::invalid_argument("truth and result need a rate");
  if (identity != nullptr &&
      (identity->track.size() != result.points.size() || identity->name.size() != result.points.size())) {
    throw std::invalid_argument("point identities are not one per cell of the result");
  }
  if (visibility != nullptr) {
    if (visibility->names != truth.names) {
      throw std::invalid_argument("visibility marker names differ from the truth's");
    }
    for (size_t f = 0; f < visibility->NumFrames(); ++f) visibility_index_[visibility->frame_numbers[f]] = f;
  }
  report_.gate_mm = options.gate_mm;
  report_.names_from_frame = options.names_from_frame;
  report_.visibility_used = visibility != nullptr;
  report_.truth_exchanges = exchanges_.count;
  report_.frames = truth.NumFrames();
  IndexNames();
  AlignFrames();
}

void MarkerScorer::IndexNames() {
  std::unordered_map<std::string, long> truth_marker_of_name;
  for (size_t m = 0; m < truth_markers_; ++m) truth_marker_of_name[truth_.names[m]] = static_cast<long>(m);
  named_as_.assign(names_.size(), -1);
  anonymous_.assign(names_.size(), 0);
  for (size_t k = 0; k < names_.size(); ++k) {
    anonymous_[k] = IsAnonymousMarkerName(names_[k]);
    const auto it = truth_marker_of_name.find(names_[k]);
    if (it != truth_marker_of_name.end() && !anonymous_[k]) named_as_[k] = it->second;
  }
  labels_ = std::any_of(named_as_.begin(), named_as_.end(), [](long m) { return m >= 0; });
}

void MarkerScorer::AlignFrames() {
  std::unordered_map<uint64_t, size_t> truth_index;
  for (size_t f = 0; f < truth_.NumFrames(); ++f) truth_index[truth_.frame_numbers[f]] = f;
  result_of_truth_.assign(truth_.NumFrames(), -1);
  for (size_t r = 0; r < result_.NumFrames(); ++r) {
    const long t = AlignedTruthFrame(truth_index, truth_.rate_hz, result_.TimeOf(r));
    if (t < 0 || result_of_truth_[t] >= 0) {
      ++report_.unaligned_result_frames;
    } else {
      result_of_truth_[t] = static_cast<long>(r);
      ++report_.result_frames;
    }
  }
}

long MarkerScorer::NameOf(size_t r, size_t column) const {
  if (identity_ == nullptr) return anonymous_[column] ? -1 : static_cast<long>(column);
  return identity_->name[r * result_markers_ + column];
}

long MarkerScorer::TrackOf(size_t r, size_t column) {
  const int64_t key =
      identity_ == nullptr ? static_cast<int64_t>(column) : identity_->track[r * result_markers_ + column];
  if (key < 0) return -1;
  return static_cast<long>(track_index_.emplace(key, track_index_.size()).first->second);
}

void MarkerScorer::Score() {
  for (size_t t = 0; t < truth_.NumFrames(); ++t) ScoreFrame(t);
}

void MarkerScorer::ScoreFrame(size_t t) {
  present_truth_.clear();
  present_result_.clear();
  for (size_t m = 0; m < truth_markers_; ++m) {
    if (truth_.Has(t, m)) {
      present_truth_.push_back(m);
      ++truth_frames_present_[m];
    }
  }
  const long r = result_of_truth_[t];
  if (r >= 0) {
    for (size_t k = 0; k < result_markers_; ++k) {
      if (result_.Has(r, k)) present_result_.push_back(k);
    }
  }
  Eigen::MatrixXd cost(present_result_.size(), present_truth_.size());
  for (size_t i = 0; i < present_result_.size(); ++i) {
    for (size_t j = 0; j < present_truth_.size(); ++j) {
      cost(i, j) = (result_.At(r, present_result_[i]) - truth_.At(t, present_truth_[j])).norm();
    }
  }
  const std::vector<int> match = SolveAssignment(cost, options_.gate_mm);
  std::vector<char> truth_matched(present_truth_.size(), 0);
  size_t frame_correct = 0, frame_points = 0;
  for (size_t i = 0; i < present_result_.size(); ++i) {
    const long marker = match[i] >= 0 ? static_cast<long>(present_truth_[match[i]]) : -1;
    ScorePoint(t, static_cast<size_t>(r), present_result_[i], marker, &frame_correct, &frame_points);
    if (marker < 0) continue;
    truth_matched[match[i]] = 1;
    errors_.push_back(cost(i, match[i]));
  }
  if (labels_ && frame_points > 0)
    worst_share_ = std::min(worst_share_, static_cast<double>(frame_correct) / frame_points);
  CountExpected(t, truth_matched);
}

void MarkerScorer::ScorePoint(size_t t, size_t r, size_t column, long marker, size_t* frame_correct,
                              size_t* frame_points) {
  ++report_.result_points;
  const long name = NameOf(r, column);
  const long track = TrackOf(r, column);
  if (marker < 0 || truth_frames_present_[marker] >= options_.names_from_frame) {
    ++report_.label_points;
    ++*frame_points;
    if (name >= 0 && named_as_[name] >= 0) {
      ++report_.named_points;
      if (named_as_[name] == marker) {
        ++report_.correctly_named;
        ++*frame_correct;
      } else {
        ++report_.wrongly_named;
      }
    } else {
      ++report_.unnamed_points;
    }
  }
  if (track >= 0) {
    if (static_cast<size_t>(track) >= tracks_.size()) tracks_.resize(track + 1);
    TrackState& state = tracks_[track];
    if (name >= 0 && !anonymous_[name]) {
      if (state.last_name >= 0 && state.last_name != name) ++state.name_changes;
      state.last_name = name;
    }
  }
  if (marker < 0) {
    ++report_.ghosts;
    return;
  }
  if (track < 0) return;
  // An id change: this truth marker is now followed by another track than it last was.
  if (last_track_of_marker_[marker] >= 0 && last_track_of_marker_[marker] != track) ++id_changes_of_marker_[marker];
  last_track_of_marker_[marker] = track;
  // A swap: this output trajectory now follows a different truth marker than it last did.
  TrackState& state = tracks_[track];
  if (state.last_match >= 0 && state.last_match != marker) {
    ++report_.swaps;
    if (exchanges_.Involves(t, marker) || exchanges_.Involves(t, static_cast<size_t>(state.last_match))) {
      ++report_.swaps_at_truth_exchanges;
    }
  }
  state.last_match = marker;
}

void MarkerScorer::CountExpected(size_t t, const std::vector<char>& truth_matched) {
  long visibility_frame = -1;
  if (visibility_ != nullptr) {
    const auto it = visibility_index_.find(truth_.frame_numbers[t]);
    if (it != visibility_index_.end()) visibility_frame = static_cast<long>(it->second);
  }
  for (size_t j = 0; j < present_truth_.size(); ++j) {
    const size_t marker = present_truth_[j];
    truth_ever_[marker] = 1;
    ++report_.truth_points;
    // Without a visibility row for this frame every present marker counts.
    const bool expected = visibility_ == nullptr || visibility_frame < 0 ||
                          visibility_->At(visibility_frame, marker) >= options_.min_cameras;
    if (!expected) continue;
    ++report_.expected_points;
    if (!truth_matched[j]) ++report_.missing;
  }
}

MarkerEvalReport MarkerScorer::Finish() {
  MarkerEvalReport& report = report_;
  report.matched = errors_.size();
  report.labels_compared = labels_;
  if (labels_ && report.label_points > 0) {
    report.correct_share = static_cast<double>(report.correctly_named) / report.label_points;
    report.wrong_share = static_cast<double>(report.wrongly_named) / report.label_points;
    report.unnamed_share = static_cast<double>(report.unnamed_points) / report.label_points;
    report.worst_frame_correct_share = worst_share_;
  }
  for (size_t changes : id_changes_of_marker_) {
    report.id_changes += changes;
    report.max_id_changes = std::max(report.max_id_changes, changes);
  }
  for (const TrackState& state : tracks_) {
    report.name_changes += state.name_changes;
    report.tracks_renamed += state.name_changes > 0;
    report.max_name_changes = std::max(report.max_name_changes, state.name_changes);
  }
  report.trajectories = track_index_.size();
  report.truth_markers = static_cast<size_t>(std::count(truth_ever_.begin(), truth_ever_.end(), 1));
  if (!errors_.empty()) {
    double sum = 0.0, sum_squares = 0.0;
    for (double e : errors_) {
      sum += e;
      sum_squares += e * e;
    }
    report.mean_error_mm = sum / errors_.size();
    report.rmse_mm = std::sqrt(sum_squares / errors_.size());
    report.max_error_mm = *std::max_element(errors_.begin(), errors_.end());
    // Nearest-rank 95th percentile.
    const size_t rank = static_cast<size_t>(std::ceil(0.95 * errors_.size())) - 1;
    std::nth_element(errors_.begin(), errors_.begin() + rank, errors_.end());
    report.p95_error_mm = errors_[rank];
  }
  if (report.frames > 0) {
    report.ghosts_per_frame = static_cast<double>(report.ghosts) / report.frames;
    report.missing_per_frame = static_cast<double>(report.missing) / report.frames;
  }
  if (report.truth_markers > 0) {
    report.fragmentation = static_cast<double>(report.trajectories) / report.truth_markers;
    report.id_changes_per_marker = static_cast<double>(report.id_changes) / report.truth_markers;
  }
  return report;
}

}  // namespace

MarkerEvalReport EvaluateMarkers(const MarkerTrajectories& truth, const MarkerTrajectories& result,
                                 const MarkerVisibility* visibility, const MarkerEvalOptions& options,
                                 const PublishedIdentity* identity) {
  MarkerScorer scorer(truth, result, visibility, options, identity);
  scorer.Score();
  return scorer.Finish();
}

nlohmann::json MarkerEvalReport::ToJson() const {
  return {{"frames", frames},
          {"result_frames", result_frames},
          {"unaligned_result_frames", unaligned_result_frames},
          {"truth_markers", truth_markers},
          {"truth_points", truth_points},
          {"expected_points", expected_points},
          {"result_points", result_points},
          {"matched", matched},
          {"rmse_mm", rmse_mm},
          {"mean_error_mm", mean_error_mm},
          {"p95_error_mm", p95_error_mm},
          {"max_error_mm", max_error_mm},
          {"ghosts", ghosts},
          {"ghosts_per_frame", ghosts_per_frame},
          {"missing", missing},
          {"missing_per_frame", missing_per_frame},
          {"trajectories", trajectories},
          {"fragmentation", fragmentation},
          {"swaps", swaps},
          {"truth_exchanges", truth_exchanges},
          {"swaps_at_truth_exchanges", swaps_at_truth_exchanges},
          {"visibility_used", visibility_used},
          {"gate_mm", gate_mm},
          {"id_changes", id_changes},
          {"id_changes_per_marker", id_changes_per_marker},
          {"max_id_changes", max_id_changes},
          {"name_changes", name_changes},
          {"tracks_renamed", tracks_renamed},
          {"max_name_changes", max_name_changes},
          {"labels_compared", labels_compared},
          {"names_from_frame", names_from_frame},
          {"label_points", label_points},
          {"named_points", named_points},
          {"correctly_named", correctly_named},
          {"wrongly_named", wrongly_named},
          {"unnamed_points", unnamed_points},
          {"correct_share", correct_share},
          {"wrong_share", wrong_share},
          {"unnamed_share", unnamed_share},
          {"worst_frame_correct_share", worst_frame_correct_share}};
}

std::string MarkerEvalReport::ToText() const {
  std::ostringstream out;
  out << fmt::format("frames            {} truth, {} aligned result rows, {} result rows at other times\n", frames,
                     result_frames, unaligned_result_frames);
  out << fmt::format("matched           {} of {} truth points ({} output points, gate {} mm)\n", matched,
                     truth_points, result_points, gate_mm);
  if (matched == 0)
    out << "rmse_mm           n/a      (no output point matched the truth)\n";
  else
    out << fmt::format("rmse_mm           {:.4f}   (mean {:.4f}, p95 {:.4f}, max {:.4f})\n", rmse_mm, mean_error_mm,
                       p95_error_mm, max_error_mm);
  out << fmt::format("ghosts_per_frame  {:.4f}   ({} ghosts)\n", ghosts_per_frame, ghosts);
  out << fmt::format("missing_per_frame {:.4f}   ({} of {} expected points{})\n", missing_per_frame, missing,
                     expected_points, visibility_used ? ", seen by >= 2 cameras" : ", all present truth counted");
  out << fmt::format("trajectories      {}   for {} truth markers (fragmentation {:.3f})\n", trajectories,
                     truth_markers, fragmentation);
  out << fmt::format("swaps             {}", swaps);
  if (truth_exchanges > 0) {
    out << fmt::format("   ({} where the truth's own markers exchange places: {} such exchanges)", swaps_at_truth_exchanges,
                       truth_exchanges);
  }
  out << "\n";
  out << fmt::format("ids               {} changes of a marker's track ({:.3f} per marker, at most {}); {} name "
                     "changes on a track ({} tracks renamed, at most {})\n",
                     id_changes, id_changes_per_marker, max_id_changes, name_changes, tracks_renamed, max_name_changes);
  if (labels_compared) {
    out << fmt::format("labels            {:.3f}% of output points correctly named, {:.3f}% wrongly, {:.3f}% unnamed "
                       "({} named of {}{}; worst frame {:.1f}% correct)\n",
                       100.0 * correct_share, 100.0 * wrong_share, 100.0 * unnamed_share, named_points, label_points,
                       names_from_frame > 1 ? fmt::format(", from each marker's frame {} on", names_from_frame) : "",
                       100.0 * worst_frame_correct_share);
  }
  return out.str();
}

}  // namespace mocap

// Metric computation for `eval`. Frames align by time (frame number / rate), so files written at
// different rates or with different Frame# numbering still compare the right instants.
#include "eval/marker_accuracy.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <sstream>
#include <stdexcept>
#include <unordered_map>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "eval/truth_exchanges.h"
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

MarkerEvalReport EvaluateMarkers(const MarkerTrajectories& truth, const MarkerTrajectories& result,
                                 const MarkerVisibility* visibility, const MarkerEvalOptions& options,
                                 const PublishedIdentity* identity) {
  options.Check();
  if (!(truth.rate_hz > 0.0) || !(result.rate_hz > 0.0)) throw std::invalid_argument("truth and result need a rate");
  const size_t truth_markers = truth.NumMarkers();
  const size_t result_markers = result.NumMarkers();
  if (identity != nullptr &&
      (identity->track.size() != result.points.size() || identity->name.size() != result.points.size())) {
    throw std::invalid_argument("point identities are not one per cell of the result");
  }

  std::unordered_map<uint64_t, size_t> visibility_index;
  if (visibility != nullptr) {
    if (visibility->names != truth.names) {
      throw std::invalid_argument("visibility marker names differ from the truth's");
    }
    for (size_t f = 0; f < visibility->NumFrames(); ++f) visibility_index[visibility->frame_numbers[f]] = f;
  }

  // Names: each point's name is an index into `names` (-1: unnamed); its truth marker, -1 for a
  // name the truth does not have and for the hub's anonymous names.
  const std::vector<std::string>& names = identity != nullptr ? identity->names : result.names;
  std::unordered_map<std::string, long> truth_marker_of_name;
  for (size_t m = 0; m < truth_markers; ++m) truth_marker_of_name[truth.names[m]] = static_cast<long>(m);
  std::vector<long> named_as(names.size(), -1);
  std::vector<char> anonymous(names.size(), 0);
  for (size_t k = 0; k < names.size(); ++k) {
    anonymous[k] = IsAnonymousMarkerName(names[k]);
    const auto it = truth_marker_of_name.find(names[k]);
    if (it != truth_marker_of_name.end() && !anonymous[k]) named_as[k] = it->second;
  }
  const bool labels = std::any_of(named_as.begin(), named_as.end(), [](long m) { return m >= 0; });
  const auto name_of = [&](size_t r, size_t column) -> long {
    if (identity == nullptr) return anonymous[column] ? -1 : static_cast<long>(column);
    return identity->name[r * result_markers + column];
  };
  // Tracks: a column of a TRC, a published id of a live result (dense indices in order seen).
  std::unordered_map<int64_t, size_t> track_index;
  const auto track_of = [&](size_t r, size_t column) -> long {
    const int64_t key = identity == nullptr ? static_cast<int64_t>(column) : identity->track[r * result_markers + column];
    if (key < 0) return -1;
    return static_cast<long>(track_index.emplace(key, track_index.size()).first->second);
  };
  double worst_share = 1.0;

  std::unordered_map<uint64_t, size_t> truth_index;
  for (size_t f = 0; f < truth.NumFrames(); ++f) truth_index[truth.frame_numbers[f]] = f;
  // For each truth frame, the aligned result frame (or none: the result wrote no row then).
  std::vector<long> result_of_truth(truth.NumFrames(), -1);
  MarkerEvalReport report;
  report.gate_mm = options.gate_mm;
  report.names_from_frame = options.names_from_frame;
  report.visibility_used = visibility != nullptr;
  for (size_t r = 0; r < result.NumFrames(); ++r) {
    const long t = AlignedTruthFrame(truth_index, truth.rate_hz, result.TimeOf(r));
    if (t < 0 || result_of_truth[t] >= 0) {
      ++report.unaligned_result_frames;
    } else {
      result_of_truth[t] = static_cast<long>(r);
      ++report.result_frames;
    }
  }

  std::vector<char> truth_ever(truth_markers, 0);
  std::vector<long> truth_frames_present(truth_markers, 0);
  std::vector<long> last_track_of_marker(truth_markers, -1);
  std::vector<size_t> id_changes_of_marker(truth_markers, 0);
  struct TrackState {
    long last_match = -1;  // truth marker
    long last_name = -1;   // index into names
    size_t name_changes = 0;
  };
  std::vector<TrackState> tracks;
  const TruthExchanges exchanges = FindTruthExchanges(truth);
  report.truth_exchanges = exchanges.count;
  std::vector<double> errors;
  std::vector<size_t> present_truth, present_result;
  report.frames = truth.NumFrames();
  for (size_t t = 0; t < truth.NumFrames(); ++t) {
    present_truth.clear();
    present_result.clear();
    for (size_t m = 0; m < truth_markers; ++m) {
      if (truth.Has(t, m)) {
        present_truth.push_back(m);
        ++truth_frames_present[m];
      }
    }
    const long r = result_of_truth[t];
    if (r >= 0) {
      for (size_t k = 0; k < result_markers; ++k) {
        if (result.Has(r, k)) present_result.push_back(k);
      }
    }
    Eigen::MatrixXd cost(present_result.size(), present_truth.size());
    for (size_t i = 0; i < present_result.size(); ++i) {
      for (size_t j = 0; j < present_truth.size(); ++j) {
        cost(i, j) = (result.At(r, present_result[i]) - truth.At(t, present_truth[j])).norm();
      }
    }
    const std::vector<int> match = SolveAssignment(cost, options.gate_mm);

    std::vector<char> truth_matched(present_truth.size(), 0);
    size_t frame_correct = 0, frame_points = 0;
    for (size_t i = 0; i < present_result.size(); ++i) {
      const size_t column = present_result[i];
      ++report.result_points;
      const long marker = match[i] >= 0 ? static_cast<long>(present_truth[match[i]]) : -1;
      const long name = name_of(static_cast<size_t>(r), column);
      const long track = track_of(static_cast<size_t>(r), column);
      if (marker < 0 || truth_frames_present[marker] >= options.names_from_frame) {
        ++report.label_points;
        ++frame_points;
        if (name >= 0 && named_as[name] >= 0) {
          ++report.named_points;
          if (named_as[name] == marker) {
            ++report.correctly_named;
            ++frame_correct;
          } else {
            ++report.wrongly_named;
          }
        } else {
          ++report.unnamed_points;
        }
      }
      if (track >= 0) {
        if (static_cast<size_t>(track) >= tracks.size()) tracks.resize(track + 1);
        TrackState& state = tracks[track];
        if (name >= 0 && !anonymous[name]) {
          if (state.last_name >= 0 && state.last_name != name) ++state.name_changes;
          state.last_name = name;
        }
      }
      if (marker < 0) {
        ++report.ghosts;
        continue;
      }
      truth_matched[match[i]] = 1;
      errors.push_back(cost(i, match[i]));
      if (track < 0) continue;
      // An id change: this truth marker is now followed by another track than it last was.
      if (last_track_of_marker[marker] >= 0 && last_track_of_marker[marker] != track) ++id_changes_of_marker[marker];
      last_track_of_marker[marker] = track;
      // A swap: this output trajectory now follows a different truth marker than it last did.
      TrackState& state = tracks[track];
      if (state.last_match >= 0 && state.last_match != marker) {
        ++report.swaps;
        if (exchanges.Involves(t, marker) || exchanges.Involves(t, static_cast<size_t>(state.last_match))) {
          ++report.swaps_at_truth_exchanges;
        }
      }
      state.last_match = marker;
    }

    if (labels && frame_points > 0)
      worst_share = std::min(worst_share, static_cast<double>(frame_correct) / frame_points);

    long visibility_frame = -1;
    if (visibility != nullptr) {
      const auto it = visibility_index.find(truth.frame_numbers[t]);
      if (it != visibility_index.end()) visibility_frame = static_cast<long>(it->second);
    }
    for (size_t j = 0; j < present_truth.size(); ++j) {
      const size_t marker = present_truth[j];
      truth_ever[marker] = 1;
      ++report.truth_points;
      // Without a visibility row for this frame every present marker counts.
      const bool expected = visibility == nullptr || visibility_frame < 0 ||
                            visibility->At(visibility_frame, marker) >= options.min_cameras;
      if (!expected) continue;
      ++report.expected_points;
      if (!truth_matched[j]) ++report.missing;
    }
  }

  report.matched = errors.size();
  report.labels_compared = labels;
  if (labels && report.label_points > 0) {
    report.correct_share = static_cast<double>(report.correctly_named) / report.label_points;
    report.wrong_share = static_cast<double>(report.wrongly_named) / report.label_points;
    report.unnamed_share = static_cast<double>(report.unnamed_points) / report.label_points;
    report.worst_frame_correct_share = worst_share;
  }
  for (size_t changes : id_changes_of_marker) {
    report.id_changes += changes;
    report.max_id_changes = std::max(report.max_id_changes, changes);
  }
  for (const TrackState& state : tracks) {
    report.name_changes += state.name_changes;
    report.tracks_renamed += state.name_changes > 0;
    report.max_name_changes = std::max(report.max_name_changes, state.name_changes);
  }
  report.trajectories = track_index.size();
  report.truth_markers = static_cast<size_t>(std::count(truth_ever.begin(), truth_ever.end(), 1));
  if (!errors.empty()) {
    double sum = 0.0, sum_squares = 0.0;
    for (double e : errors) {
      sum += e;
      sum_squares += e * e;
    }
    report.mean_error_mm = sum / errors.size();
    report.rmse_mm = std::sqrt(sum_squares / errors.size());
    report.max_error_mm = *std::max_element(errors.begin(), errors.end());
    // Nearest-rank 95th percentile.
    const size_t rank = static_cast<size_t>(std::ceil(0.95 * errors.size())) - 1;
    std::nth_element(errors.begin(), errors.begin() + rank, errors.end());
    report.p95_error_mm = errors[rank];
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
